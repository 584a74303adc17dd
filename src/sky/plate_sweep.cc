// Plates' pixels held only while the PQ rows they reach are current: a sweep in order of first row.
#include "sky/plate_sweep.h"

#include <algorithm>

namespace gdp::sky {

PlatePixels::PlatePixels(std::vector<Plate>& plates, std::vector<Plate>& finders, const PqWindow& window, int lag)
    : plates_(plates), finders_(finders), holding_(plates.size(), 0), lag_(lag) {
  for (std::size_t k = 0; k < plates.size(); ++k) {
    rows_.push_back(plate_rows(plates[k], window, kExtension));
    columns_.push_back(plate_columns(plates[k], window, kExtension));
    if (!finders.empty()) {
      const auto f = plate_rows(finders[k], window, kExtension), c = plate_columns(finders[k], window, kExtension);
      rows_[k] = {std::min(rows_[k][0], f[0]), std::max(rows_[k][1], f[1])};
      columns_[k] = {std::min(columns_[k][0], c[0]), std::max(columns_[k][1], c[1])};
    }
  }
}

void PlatePixels::hold(std::size_t k) {
  if (holding_[k]) return;
  read_pixels(plates_[k]);
  if (!backgrounds_.empty()) subtract_smooth_background(plates_[k], backgrounds_[k]);
  if (!finders_.empty()) read_pixels(finders_[k]);
  pixels_read_ += (finders_.empty() ? 1LL : 2LL) * plates_[k].width * plates_[k].height;
  holding_[k] = 1;
  most_held_ = std::max(most_held_, ++held_);
}

void PlatePixels::release(std::size_t k) {
  if (!holding_[k]) return;
  std::vector<float>().swap(plates_[k].pixels);
  if (!finders_.empty()) std::vector<float>().swap(finders_[k].pixels);
  holding_[k] = 0;
  --held_;
}

std::size_t PlatePixels::most_crossing() const {
  // +1 at each first row, -1 after each last row (and its lag): the running sum's maximum.
  std::vector<std::pair<long long, int>> events;
  for (const auto& r : rows_) events.insert(events.end(), {{r[0], 1}, {static_cast<long long>(r[1]) + lag_ + 1, -1}});
  std::sort(events.begin(), events.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first < b.first : a.second < b.second;  // ends before starts on a row
  });
  long long now = 0, most = 0;
  for (const auto& e : events) most = std::max(most, now += e.second);
  return static_cast<std::size_t>(most);
}

void PlatePixels::sweep(const Visit& visit, const std::vector<char>& only) {
  std::vector<std::size_t> order, held;
  for (std::size_t k = 0; k < plates_.size(); ++k)
    if (only.empty() || only[k]) order.push_back(k);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return rows_[a][0] < rows_[b][0]; });
  for (const std::size_t k : order) {
    std::erase_if(held, [&](std::size_t q) {
      if (rows_[q][1] >= rows_[k][0]) return false;
      release(q);
      return true;
    });
    hold(k);
    visit(k, held);
    held.push_back(k);
  }
  for (const std::size_t q : held) release(q);
}

}  // namespace gdp::sky
