// Rank-shared plate passes: packing each rank's plates' results and the ordered gather and broadcast of bands/transport.h.
#include "sky/plate_exchange.h"

#include <exception>

namespace gdp::sky {
namespace {

enum Tag { kDetections = 1, kSamples, kBackgrounds, kLevels, kCounts };

using schedule::Bytes;
using Packer = schedule::ByteWriter;
using Unpacker = schedule::ByteReader;

double next(Unpacker& in) {
  double v;
  in.io(v);
  return v;
}

// A rank's records: their count, then each as `put` writes it.
template <class F>
Bytes records(std::size_t count, F&& put) {
  Packer out;
  out.io(double(count));
  put(out);
  return std::move(out.bytes);
}

// Every rank's records (records()), in rank order, to every rank, each read by `read`.
template <class F>
void all_gather(const PlateShare& share, int tag, Bytes mine, F&& read) {
  for (Bytes& part : bands::all_gather(*share.net, tag, std::move(mine))) {
    Unpacker in(std::move(part));
    for (std::size_t n = static_cast<std::size_t>(next(in)); n > 0; --n) read(in);
    in.finish();
  }
}

}  // namespace

void PlateShare::run(const std::function<void()>& step) const {
  if (!net || size() == 1) return step();
  std::string error;
  try {
    step();
  } catch (const std::exception& e) {
    error = e.what();
  }
  agree(error);
}

void share_detections(const PlateShare& share, std::vector<std::vector<SourceDetection>>& detections) {
  if (share.size() == 1) return;
  std::size_t owned = 0;
  for (std::size_t k = 0; k < detections.size(); ++k) owned += share.owns(k);
  Bytes mine = records(owned, [&](Packer& out) {
    for (std::size_t k = 0; k < detections.size(); ++k) {
      if (!share.owns(k)) continue;
      out.io(double(k));
      out.io(double(detections[k].size()));
      for (const SourceDetection& d : detections[k]) {
        out.put(&d.centre, 1);
        out.io(d.radius);
        out.io(d.hits);
      }
    }
  });
  all_gather(share, kDetections, std::move(mine), [&](Unpacker& in) {
    std::vector<SourceDetection>& list = detections[static_cast<std::size_t>(next(in))];
    list.resize(static_cast<std::size_t>(next(in)));
    for (SourceDetection& d : list) {
      in.get(&d.centre, 1);
      d.radius = next(in);
      in.io(d.hits);
    }
  });
}

void SampleBlocks::add(int a, int b, const std::vector<OverlapSample>& samples) {
  const double pair[2] = {double(a), double(b)};
  out_.put(pair, 2);
  out_.io(samples);
  ++count_;
}

bands::Bytes SampleBlocks::take() {
  Packer head;
  head.io(double(count_));
  head.bytes.insert(head.bytes.end(), out_.bytes.begin(), out_.bytes.end());
  return std::move(head.bytes);
}

void gather_samples(const PlateShare& share, SampleBlocks& mine,
                    const std::function<void(int a, int b, const std::vector<OverlapSample>&)>& add) {
  if (share.size() == 1) return;
  std::vector<Bytes> parts = bands::gather(*share.net, kSamples, mine.take());
  std::vector<OverlapSample> samples;
  for (std::size_t r = 1; r < parts.size(); ++r) {
    Unpacker in(std::move(parts[r]));
    for (std::size_t n = static_cast<std::size_t>(next(in)); n > 0; --n) {
      const int a = static_cast<int>(next(in)), b = static_cast<int>(next(in));
      in.io(samples);
      add(a, b, samples);
    }
    in.finish();
  }
}

void share_backgrounds(const PlateShare& share, std::vector<PlateBackground>& backgrounds, std::size_t& samples) {
  if (share.size() == 1) return;
  std::vector<double> terms{double(samples)};  // the count, then each plate's four terms
  for (const PlateBackground& b : backgrounds) terms.insert(terms.end(), {b.offset, b.slope_u, b.slope_v, b.radial});
  Packer out;
  out.io(terms);
  Unpacker in(bands::broadcast(*share.net, kBackgrounds, std::move(out.bytes)));
  in.io(terms);
  in.finish();
  samples = static_cast<std::size_t>(terms[0]);
  backgrounds.resize((terms.size() - 1) / 4);
  for (std::size_t k = 0; k < backgrounds.size(); ++k)
    backgrounds[k] = {terms[1 + 4 * k], terms[2 + 4 * k], terms[3 + 4 * k], terms[4 + 4 * k]};
}

void share_levels(const PlateShare& share, std::vector<Plate>& plates, std::map<std::pair<int, int>, OverlapSum>& sums) {
  if (share.size() == 1) return;
  std::size_t owned = 0;
  for (std::size_t k = 0; k < plates.size(); ++k) owned += share.owns(k);
  for (const auto& [ab, o] : sums) owned += share.owns(static_cast<std::size_t>(ab.first));
  Bytes mine = records(owned, [&](Packer& out) {
    for (std::size_t k = 0; k < plates.size(); ++k)
      if (share.owns(k)) {
        const double head[3] = {0.0, double(k), plates[k].mean};
        out.put(head, 3);
        out.io(plates[k].edge_correction);
      }
    for (const auto& [ab, o] : sums)
      if (share.owns(static_cast<std::size_t>(ab.first))) {
        const double pair[5] = {1.0, double(o.a), double(o.b), o.sum, double(o.n)};
        out.put(pair, 5);
      }
  });
  all_gather(share, kLevels, std::move(mine), [&](Unpacker& in) {
    if (next(in) == 0.0) {  // a plate's
      Plate& p = plates[static_cast<std::size_t>(next(in))];
      p.mean = next(in);
      in.io(p.edge_correction);
      return;
    }
    OverlapSum o;  // a pair's
    o.a = static_cast<int>(next(in));
    o.b = static_cast<int>(next(in));
    o.sum = next(in);
    o.n = static_cast<long long>(next(in));
    sums[{o.a, o.b}] = o;
  });
}

std::vector<long long> counts_by_rank(const PlateShare& share, long long mine) {
  std::vector<double> all(share.size(), 0.0);  // exact: each slot is one rank's count plus zeros
  all[share.rank()] = static_cast<double>(mine);
  if (share.net) bands::sum_in_order(*share.net, kCounts, all);
  return {all.begin(), all.end()};
}

}  // namespace gdp::sky
