// Rank-shared plate passes: packing each rank's plates' results and the ordered gather and broadcast of bands/transport.h.
#include "sky/plate_exchange.h"

#include <cstdint>
#include <exception>

namespace gdp::sky {
namespace {

enum Tag { kDetections = 1, kSamples, kBackgrounds, kLevels, kCounts, kCanvasLevels };

using schedule::ByteReader;
using schedule::ByteWriter;
using schedule::Bytes;

// A rank's records: their count, then each as `put` writes it.
template <class F>
Bytes records(std::uint64_t count, F&& put) {
  ByteWriter out;
  out.io(count);
  put(out);
  return std::move(out.bytes);
}

// Each of the records in `part` (records()) read by `read`.
template <class F>
void read_records(Bytes part, F&& read) {
  ByteReader in(std::move(part));
  std::uint64_t n = 0;
  for (in.io(n); n > 0; --n) read(in);
  in.finish();
}

// Every rank's records, in rank order, to every rank, each read by `read`.
template <class F>
void all_gather(const PlateShare& share, int tag, Bytes mine, F&& read) {
  for (Bytes& part : bands::all_gather(*share.net, tag, std::move(mine))) read_records(std::move(part), read);
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
  std::uint64_t owned = 0;
  for (std::size_t k = 0; k < detections.size(); ++k) owned += share.owns(k);
  Bytes mine = records(owned, [&](ByteWriter& out) {
    for (std::uint64_t k = 0; k < detections.size(); ++k) {
      if (!share.owns(k)) continue;
      out.io(k);
      out.io(static_cast<std::uint64_t>(detections[k].size()));
      for (const SourceDetection& d : detections[k]) {
        out.io(d.centre);
        out.io(d.radius);
        out.io(d.hits);
      }
    }
  });
  all_gather(share, kDetections, std::move(mine), [&](ByteReader& in) {
    std::uint64_t k = 0, n = 0;
    in.io(k);
    in.io(n);
    std::vector<SourceDetection>& list = detections[k];
    list.resize(n);
    for (SourceDetection& d : list) {
      in.io(d.centre);
      in.io(d.radius);
      in.io(d.hits);
    }
  });
}

void SampleBlocks::add(int a, int b, const std::vector<OverlapSample>& samples) {
  const int pair[2] = {a, b};
  out_.put(pair, 2);
  out_.io(samples);
  ++count_;
}

bands::Bytes SampleBlocks::take() {
  return records(count_, [&](ByteWriter& out) { out.put(out_.bytes.data(), out_.bytes.size()); });
}

void gather_samples(const PlateShare& share, SampleBlocks& mine,
                    const std::function<void(int a, int b, const std::vector<OverlapSample>&)>& add) {
  if (share.size() == 1) return;
  std::vector<Bytes> parts = bands::gather(*share.net, kSamples, mine.take());
  std::vector<OverlapSample> samples;
  for (std::size_t r = 1; r < parts.size(); ++r)
    read_records(std::move(parts[r]), [&](ByteReader& in) {
      int pair[2];
      in.get(pair, 2);
      in.io(samples);
      add(pair[0], pair[1], samples);
    });
}

void share_backgrounds(const PlateShare& share, std::vector<PlateBackground>& backgrounds, std::size_t& samples) {
  if (share.size() == 1) return;
  ByteWriter out;
  out.io(static_cast<std::uint64_t>(samples));
  out.io(backgrounds);
  ByteReader in(bands::broadcast(*share.net, kBackgrounds, std::move(out.bytes)));
  std::uint64_t fitted = 0;
  in.io(fitted);
  in.io(backgrounds);
  in.finish();
  samples = fitted;
}

void share_levels(const PlateShare& share, std::vector<Plate>& plates, std::map<std::pair<int, int>, OverlapSum>& sums) {
  if (share.size() == 1) return;
  enum Kind : std::uint8_t { kPlate, kPair };  // a record's first byte
  std::uint64_t owned = 0;
  for (std::size_t k = 0; k < plates.size(); ++k) owned += share.owns(k);
  for (const auto& [ab, o] : sums) owned += share.owns(static_cast<std::size_t>(ab.first));
  Bytes mine = records(owned, [&](ByteWriter& out) {
    for (std::uint64_t k = 0; k < plates.size(); ++k)
      if (share.owns(k)) {
        out.io(kPlate);
        out.io(k);
        out.io(plates[k].mean);
        out.io(plates[k].edge_correction);
      }
    for (const auto& [ab, o] : sums)
      if (share.owns(static_cast<std::size_t>(ab.first))) {
        out.io(kPair);
        out.io(o);
      }
  });
  all_gather(share, kLevels, std::move(mine), [&](ByteReader& in) {
    Kind kind = kPlate;
    in.io(kind);
    if (kind == kPlate) {
      std::uint64_t k = 0;
      in.io(k);
      Plate& p = plates[k];
      in.io(p.mean);
      in.io(p.edge_correction);
      return;
    }
    OverlapSum o;
    in.io(o);
    sums[{o.a, o.b}] = o;
  });
}

void share_canvas_levels(const PlateShare& share, CanvasLevels& levels) {
  if (share.size() == 1) return;
  ByteWriter out;
  out.io(levels.offsets);
  out.io(levels.backgrounds);
  out.io(levels.overlapped);
  ByteReader in(bands::broadcast(*share.net, kCanvasLevels, std::move(out.bytes)));
  in.io(levels.offsets);
  in.io(levels.backgrounds);
  in.io(levels.overlapped);
  in.finish();
}

std::vector<long long> counts_by_rank(const PlateShare& share, long long mine) {
  if (share.size() == 1) return {mine};
  ByteWriter out;
  out.io(mine);
  std::vector<long long> all;
  for (Bytes& part : bands::all_gather(*share.net, kCounts, std::move(out.bytes))) {
    ByteReader in(std::move(part));
    in.io(all.emplace_back());
    in.finish();
  }
  return all;
}

}  // namespace gdp::sky
