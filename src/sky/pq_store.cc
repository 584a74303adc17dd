// Rows of the solved PQ image in scratch, and what is computed from them in one pass.
#include "sky/pq_store.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "blend/scratch.h"

namespace gdp::sky {

PqStore::PqStore(const PqWindow& window, const std::filesystem::path& temp_dir, std::size_t memory_limit)
    : window_(window),
      rows_(std::make_unique<blending::Scratch>(
          temp_dir, static_cast<std::size_t>(window.width) * window.rows * sizeof(float), "gdp-sky-pq", memory_limit)) {}

PqStore::PqStore(const Image& pq, const PqWindow& window) : PqStore(window, {}) {
  for (int j = 0; j < window.rows; ++j) write_row(j, pq.row(0, j));
}

PqStore::~PqStore() = default;

void PqStore::write_row(int j, std::span<const float> row) {
  rows_->write(static_cast<std::size_t>(j) * window_.width * sizeof(float), row.data(), window_.width * sizeof(float));
}

void PqStore::read_row(int j, std::span<float> row) const {
  rows_->read(static_cast<std::size_t>(j) * window_.width * sizeof(float), row.data(), window_.width * sizeof(float));
}

std::pair<float, float> display_range(const PqStore& pq) {
  // Every stride-th pixel of the row-major window, as display_range(const Image&) takes them.
  const std::size_t width = pq.window().width, size = width * pq.window().rows;
  const std::size_t stride = std::max<std::size_t>(1, size / (std::size_t{1} << 20));
  std::vector<float> sample, row(width);
  std::size_t next = 0;
  for (int j = 0; j < pq.window().rows && next < size; ++j) {
    const std::size_t first = static_cast<std::size_t>(j) * width;
    if (next >= first + width) continue;
    pq.read_row(j, row);
    for (; next < first + width; next += stride)
      if (std::isfinite(row[next - first])) sample.push_back(row[next - first]);
  }
  float lo = 0.0f, hi = 1.0f;
  if (!sample.empty()) {
    const auto at = [&](double q) {
      auto it = sample.begin() + static_cast<std::ptrdiff_t>(q * (sample.size() - 1));
      std::nth_element(sample.begin(), it, sample.end());
      return *it;
    };
    lo = at(0.005);
    hi = at(0.995);
    if (!(hi > lo)) hi = lo + 1.0f;
  }
  return {lo, hi};
}

}  // namespace gdp::sky
