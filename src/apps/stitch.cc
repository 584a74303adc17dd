// Seamless stitching, streamed: composite gradients, cut where labels change.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <unordered_map>

#include <fmt/format.h>

#include "apps/colour_space.h"
#include "apps/fidelity_guidance.h"
#include "apps/image_guidance.h"
#include "apps/output_fixups.h"
#include "gdp/apps.h"
#include "gdp/errors.h"
#include "multigrid/masked.h"

namespace gdp {
namespace {

constexpr int kUnknown = -1;

// Label colours to small integers, row by row; the same colour always gets the same id.
class LabelIds {
 public:
  LabelIds(int width, int channels, bool white_is_label)
      : width_(width), channels_(channels), white_is_label_(white_is_label), key_(channels * sizeof(float), '\0') {}
  // ids[i] for the columns [begin, end) of a label row (the others are left as they are). Most
  // pixels share their left neighbour's label: where the label changes is marked first (a loop
  // over the channels that vectorises), then each run of one label gets its id.
  void assign(std::span<const float> labels, std::vector<int>& ids, int begin, int end) {
    ids.resize(width_);
    if (begin >= end) return;
    changed_.resize(width_);
    unsigned char* changed = changed_.data();
    std::fill(changed + begin, changed + end, 0);
    for (int c = 0; c < channels_; ++c) {
      const float* l = labels.data() + static_cast<std::size_t>(c) * width_;
      for (int i = begin + 1; i < end; ++i) changed[i] |= l[i] != l[i - 1];
    }
    int start = begin;
    const auto run = [&](int next) {
      std::fill(ids.begin() + start, ids.begin() + next, id_at(labels, start));
      start = next;
    };
    multigrid::for_each_set(changed, begin + 1, end, run);
    run(end);
  }
  int count() const { return static_cast<int>(ids_.size()); }

 private:
  int id_at(std::span<const float> labels, int i) {
    bool white = true;
    for (int c = 0; c < channels_; ++c) {
      const float v = labels[static_cast<std::size_t>(c) * width_ + i];
      white = white && v == 1.0f;
      std::memcpy(key_.data() + c * sizeof(float), &v, sizeof(float));
    }
    if (white && !white_is_label_) return kUnknown;
    return ids_.try_emplace(key_, static_cast<int>(ids_.size())).first->second;
  }

  int width_, channels_;
  bool white_is_label_;
  std::string key_;
  std::unordered_map<std::string, int> ids_;
  std::vector<unsigned char> changed_;  // assign(): where the label differs from the left neighbour
};

class StitchGuidance final : public apps::ImageGuidance {
 public:
  StitchGuidance(RowReader& composite, RowReader& labels, RowReader* across, const StitchOptions& options,
                 apps::OutputFixups& fixups)
      : ImageGuidance(composite, 0.0, 1.0, options.start_from_composite),
        labels_(labels), across_(across), black_(options.unknown == UnknownMode::Black),
        extend_(options.unknown == UnknownMode::Extend), fixups_(fixups),
        ids_(composite.width(), labels.channels(), options.unknown == UnknownMode::Label),
        label_row_(static_cast<std::size_t>(labels.channels()) * labels.width()), zero_(composite.width()) {
    set_slots(slots());
    if (options.deramp) compute_ramps(composite);
  }
  // Whether a known label was met (in a window narrower than the image, other processes see
  // the other columns: true).
  bool label_seen() const { return ids_.count() > 0 || windowed(); }
  void set_columns(int begin, int end) override {
    ImageGuidance::set_columns(begin, end);
    labels_.set_columns(begin, std::min(end + 1, width()));
    if (across_) across_->set_columns(begin, std::min(end + 1, width()));
  }
  bool splits() const override { return true; }
  void set_slots(int slots) override {
    ImageGuidance::set_slots(slots);
    row_ids_.assign(slots, std::vector<int>(width()));
    across_rows_.assign(across_ ? slots : 0, std::vector<float>(2 * static_cast<std::size_t>(channels()) * width(), 0.0f));
  }
  void compute(int j, GuidanceRow& out, int begin, int end) const override {
    ImageGuidance::compute(j, out, begin, end);
    const std::vector<int>& id = row_ids_[slot(j)];
    for (int i = begin; i < end; ++i) out.counted[i] = id[i] != kUnknown;
  }

 protected:
  void on_source_row(int y, std::span<const float> row) override {
    // The label columns read: the computed ones and the one beyond, whose label the last
    // horizontal edge needs.
    const int a = column_begin(), b = std::min(column_end() + 1, width());
    labels_.read_row(y, label_row_);
    ids_.assign(label_row_, row_ids_[slot(y)], a, b);
    if (across_) across_->read_row(y, across_rows_[slot(y)]);
    if (!black_) return fixups_.record(y, row);  // no pixel is blacked out
    const int* id = row_ids_[slot(y)].data();
    unsigned char* zero = zero_.data();  // a local: the flags' stores could alias the member
    for (int i = a; i < b; ++i) zero[i] = id[i] == kUnknown;  // vectorised
    fixups_.record(y, row, zero_);
  }
  void keep_edges(int j, int begin, int end, std::span<unsigned char> right, std::span<unsigned char> down,
                  std::span<unsigned char> above) const override {
    const int w = width();
    const std::vector<int>& here = row_ids_[slot(j)];
    if (j + 1 < height()) {  // vectorised: whether labels join, then across values where they change
      const int* h = here.data();
      const int* n = row_ids_[slot(j + 1)].data();
      const int inner = std::min(end, w - 1);
      const bool extend = extend_;  // a local: the flags' stores could alias a member
      unsigned char* r = right.data();
      unsigned char* d = down.data();
      for (int i = begin; i < inner; ++i) r[i] = joins(h[i], h[i + 1], extend);
      for (int i = std::max(begin, inner); i < end; ++i) r[i] = joins(h[i], h[0], extend);  // the periodic row's last
      for (int i = begin; i < end; ++i) d[i] &= joins(h[i], n[i], extend);
      if (across_)
        for (int i = begin; i < end; ++i) {
          if (i % 8 == 0 && i + 8 <= end) {  // eight pixels at a time while every edge is kept
            std::uint64_t kept_right, kept_down;
            std::memcpy(&kept_right, r + i, 8);
            std::memcpy(&kept_down, d + i, 8);
            if ((kept_right & kept_down) == 0x0101010101010101u) {
              i += 7;
              continue;
            }
          }
          if (!right[i]) right[i] = across_either(i, j, i + 1 < w ? i + 1 : 0, j, true);
          if (!down[i] && h[i] != n[i]) down[i] = across_either(i, j, i, j + 1, false);
        }
    } else {  // the last row: only a spherical domain's folded edges go down
      for (int i = begin; i < end; ++i) {
        const int a = here[i], r = i + 1 < w ? i + 1 : 0, d = below(i, j);
        right[i] = joined(a, here[r]) || across_either(i, j, r, j, true);
        down[i] = down[i] && joined(a, here[d]);
      }
    }
    for (std::size_t i = 0; i < above.size(); ++i) above[i] = joined(here[i], here[this->above(static_cast<int>(i))]);
  }
  bool has_offsets() const override { return !ramp_.empty() || across_; }
  // Without ramps only label changes between known labels have offsets (offset() is 0 elsewhere).
  bool offset_edges(int j, int begin, int end, std::span<unsigned char> right,
                    std::span<unsigned char> down) const override {
    if (!ramp_.empty()) return false;
    const int w = width();
    const std::vector<int>& here = row_ids_[slot(j)];
    const auto change = [](int a, int b) {  // vectorised
      return static_cast<unsigned char>((a != b) & (a != kUnknown) & (b != kUnknown));
    };
    const int inner = std::min(end, w - 1);
    const int* h = here.data();
    unsigned char* r = right.data();
    for (int i = begin; i < inner; ++i) r[i] = change(h[i], h[i + 1]);
    for (int i = std::max(begin, inner); i < end; ++i) r[i] = change(h[i], h[0]);  // the periodic row's last
    if (j + 1 < height()) {
      const int* n = row_ids_[slot(j + 1)].data();
      unsigned char* d = down.data();
      for (int i = begin; i < end; ++i) d[i] = change(h[i], n[i]);
    }
    return true;
  }
  // Across a label change (with `across`) from p (source A) to q (source B), the composite's
  // difference B(q) - A(p) less the guidance kept: the mean of A's and B's differences where the
  // across values A(q) and B(p) (of the edge's direction) are both finite, else the one source's
  // difference that is known (A's where only A(q) is: B does not reach p; B's where only B(p) is).
  // Inside a label: its ramp (--deramp).
  double offset(int c, int i, int j, bool horizontal) const override {
    const int a = id(i, j), i2 = horizontal ? (i + 1 < width() ? i + 1 : 0) : i, j2 = horizontal ? j : j + 1;
    const int b = id(i2, j2);
    if (a != b && a != kUnknown && b != kUnknown) {
      const std::size_t p = static_cast<std::size_t>(c) * width() + i, q = static_cast<std::size_t>(c) * width() + i2;
      const std::size_t plane = horizontal ? 0 : static_cast<std::size_t>(channels()) * width();
      const double a_p = source_row(j)[p], b_q = source_row(j2)[q];
      const double b_p = across_rows_[slot(j)][plane + p], a_q = across_rows_[slot(j2)][plane + q];
      if (!std::isfinite(b_p)) return b_q - a_q;  // keeps A(q) - A(p)
      if (!std::isfinite(a_q)) return b_p - a_p;  // keeps B(q) - B(p)
      return 0.5 * ((b_q - a_p) - (a_q - b_p));
    }
    if (ramp_.empty() || a == kUnknown || a != b) return 0.0;
    return ramp_[(static_cast<std::size_t>(a) * channels() + c) * 2 + (horizontal ? 0 : 1)];
  }

 private:
  int id(int i, int j) const { return row_ids_[slot(j)][i]; }
  // The edge between two pixels keeps the composite's difference: same label, or (Extend) either unknown.
  bool joined(int a, int b) const { return a == b ? a != kUnknown : extend_ && (a == kUnknown || b == kUnknown); }
  // The same without branches (vectorised), as a flag.
  static unsigned char joins(int a, int b, bool extend) {
    return static_cast<unsigned char>(((a == b) & (a != kUnknown)) |
                                      ((a != b) & extend & ((a == kUnknown) | (b == kUnknown))));
  }
  // With `across`, a label change whose across values (of the edge's direction) are finite at
  // either end (first channel).
  bool across_either(int i, int j, int i2, int j2, bool horizontal) const {
    if (!across_) return false;
    const int a = id(i, j), b = id(i2, j2);
    const std::size_t plane = horizontal ? 0 : static_cast<std::size_t>(channels()) * width();
    return a != b && a != kUnknown && b != kUnknown &&
           (std::isfinite(across_rows_[slot(j)][plane + i]) || std::isfinite(across_rows_[slot(j2)][plane + i2]));
  }

  // A first pass over both inputs: the mean horizontal and vertical difference inside each
  // label, per channel. Then both are rewound for the solve.
  void compute_ramps(RowReader& composite) {
    const int w = width(), h = height(), ch = channels();
    std::vector<double> sum, count;
    std::vector<float> rows[2];
    for (auto& r : rows) r.resize(static_cast<std::size_t>(ch) * w);
    std::vector<int> ids[2];
    for (int y = 0; y < h; ++y) {
      composite.read_row(y, rows[y % 2]);
      labels_.read_row(y, label_row_);
      ids_.assign(label_row_, ids[y % 2], 0, w);
      sum.resize(static_cast<std::size_t>(ids_.count()) * ch * 2, 0.0);
      count.resize(static_cast<std::size_t>(ids_.count()) * 2, 0.0);
      const auto add = [&](int a, int dir, int i0, int y0, int i1, int y1) {
        count[a * 2 + dir] += 1.0;
        for (int c = 0; c < ch; ++c)
          sum[(static_cast<std::size_t>(a) * ch + c) * 2 + dir] +=
              double(rows[y1 % 2][static_cast<std::size_t>(c) * w + i1]) - rows[y0 % 2][static_cast<std::size_t>(c) * w + i0];
      };
      for (int i = 0; i < w; ++i) {
        const int a = ids[y % 2][i];
        if (a == kUnknown) continue;
        if (i + 1 < w && ids[y % 2][i + 1] == a) add(a, 0, i, y, i + 1, y);
        if (y > 0 && ids[(y - 1) % 2][i] == a) add(a, 1, i, y - 1, i, y);
      }
    }
    ramp_.assign(sum.size(), 0.0);
    for (std::size_t k = 0; k < sum.size(); ++k) {
      const double n = count[(k / (2 * ch)) * 2 + k % 2];
      if (n > 0.0 && std::isfinite(sum[k])) ramp_[k] = sum[k] / n;
    }
    composite.rewind();
    labels_.rewind();
  }

  RowReader& labels_;
  RowReader* across_;
  std::vector<std::vector<float>> across_rows_;  // per slot, as row_ids_
  bool black_, extend_;
  apps::OutputFixups& fixups_;
  LabelIds ids_;
  std::vector<float> label_row_;
  std::vector<std::vector<int>> row_ids_;
  std::vector<unsigned char> zero_;
  std::vector<double> ramp_;
};

}  // namespace

void check_stitch_inputs(const RowReader& composite, const RowReader& labels, const StitchOptions& options) {
  if (labels.width() != composite.width() || labels.height() != composite.height())
    throw InputError(fmt::format("{}: label map of {}x{}, but the composite{} is {}x{}", options.labels_name,
                                 labels.width(), labels.height(),
                                 options.composite_name.empty() ? "" : " " + options.composite_name,
                                 composite.width(), composite.height()));
}

void stitch(RowReader& composite, RowReader& labels, const StitchOptions& options, const SolverOptions& solver,
            RowWriter& out, SolveSummary* summary, const Fidelity& fidelity) {
  check_stitch_inputs(composite, labels, options);
  if (options.space.kind == BlendSpace::Kind::Lab && composite.channels() < 3)
    throw UsageError(fmt::format("--space lab needs an RGB composite, this one has {} channel(s)", composite.channels()));
  if (options.across && (options.across->width() != composite.width() || options.across->height() != composite.height() ||
                         options.across->channels() != 2 * composite.channels()))
    throw InputError(fmt::format("across image is {}x{}x{} but the composite is {}x{}x{} (across: twice its channels)",
                                 options.across->width(), options.across->height(), options.across->channels(),
                                 composite.width(), composite.height(), composite.channels()));
  apps::OutputFixups fixups(out, composite.width(), composite.height(), composite.channels(), solver);
  apps::SpaceReader in_space(composite, options.space);
  std::optional<apps::SpaceReader> across_space;
  if (options.across) across_space.emplace(*options.across, options.space, 2);
  apps::SpaceWriter out_space(fixups, options.space, composite.width(), composite.channels());
  StitchGuidance guidance(in_space, labels, across_space ? &*across_space : nullptr, options, fixups);
  apps::solve_with_fidelity(guidance, fidelity, solver, out_space, summary);
  if (!guidance.label_seen())
    throw InputError(fmt::format("{}: every pixel is white (unknown), so no pixel has a source and there is nothing "
                                 "to stitch (--unknown label takes white for a label)",
                                 options.labels_name));
}

Image stitch(const Image& composite, const Image& labels, const StitchOptions& options, const SolverOptions& solver,
             SolveSummary* summary) {
  ImageRowReader c(composite), l(labels);
  Image out(composite.width, composite.height, composite.channels);
  ImageRowWriter writer(out);
  stitch(c, l, options, solver, writer, summary);
  return out;
}

}  // namespace gdp
