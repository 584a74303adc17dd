// Column runs exchanged between bands: across a spherical level's fold (from the layout and the mirror map), at a merge.
#include "bands/band_fold.h"

namespace gdp::bands {
namespace {

// Which of the n columns wrap([r.first, r.second)) covers.
std::vector<char> covered(int n, std::pair<int, int> r) {
  std::vector<char> in(n, 0);
  for (int i = r.first; i < r.second && i < r.first + n; ++i) in[fem::wrap_index(i, n)] = 1;
  return in;
}

// The columns x in wrap([held)) whose mirror image (fem::mirror_column(side, x, n)) lies in
// wrap([mirrored)); ranges are in unwrapped global columns.
ColumnRuns fold_columns(int n, fem::Mirror side, std::pair<int, int> held, std::pair<int, int> mirrored) {
  const std::vector<char> have = covered(n, held), want = covered(n, mirrored);
  ColumnRuns runs;
  for (int x = 0; x < n; ++x) {
    if (!have[x] || !want[fem::mirror_column(side, x, n)]) continue;
    if (!runs.empty() && runs.back().second == x) ++runs.back().second;
    else runs.emplace_back(x, x + 1);
  }
  return runs;
}

std::pair<int, int> own(const BandLayout& L, int l, int b) { return {L.begin(l, b), L.end(l, b)}; }
std::pair<int, int> stored(const BandLayout& L, int l, int b) { return {L.origin(l, b), L.end(l, b) + L.halo}; }

template <class Held, class Mirrored>
FoldPlan plan(const BandLayout& L, int n, fem::Mirror side, int band, Held held, Mirrored mirrored) {
  FoldPlan p;
  for (int b = 0; b < L.bands; ++b) {
    p.to.push_back(fold_columns(n, side, held(band, b), mirrored(band, b)));
    p.from.push_back(fold_columns(n, side, held(b, band), mirrored(b, band)));
  }
  return p;
}

}  // namespace

FoldPlan fold_reads(const BandLayout& L, int l, int n, fem::Mirror side, int band) {
  // Sender s -> receiver r: the columns s owns whose mirror r stores.
  return plan(L, n, side, band, [&](int s, int) { return own(L, l, s); }, [&](int, int r) { return stored(L, l, r); });
}

FoldPlan fold_sums(const BandLayout& L, int l, int n, fem::Mirror side, int band) {
  // Sender s -> receiver r: the columns r owns that mirror columns s restricts into.
  return plan(L, n, side, band, [&](int, int r) { return own(L, l, r); }, [&](int s, int) { return own(L, l, s); });
}

FoldPlan group_plan(const BandLayout& L, int l, int band, int first, int end, bool to_first) {
  const auto cols = [&](int b) { return ColumnRuns{to_first ? own(L, l, b) : stored(L, l, b)}; };
  FoldPlan p{std::vector<ColumnRuns>(L.bands), std::vector<ColumnRuns>(L.bands)};
  if (band < first || band >= end) return p;
  if (band != first) (to_first ? p.to : p.from)[first] = cols(band);
  else
    for (int b = first; b < end; ++b) (to_first || b == first ? p.from : p.to)[b] = cols(b);
  return p;
}

}  // namespace gdp::bands
