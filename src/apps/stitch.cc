// Seamless stitching: composite gradients, cut where labels change; means matched afterwards.
#include <cmath>
#include <cstring>
#include <string>
#include <unordered_map>

#include <fmt/format.h>

#include "apps/image_guidance.h"
#include "gdp/apps.h"
#include "gdp/errors.h"

namespace gdp {
namespace {

constexpr int kUnknown = -1;

// One integer per pixel naming its label colour; kUnknown for white unless it is a label.
std::vector<int> label_ids(const Image& labels, bool white_is_label, int* count) {
  std::unordered_map<std::string, int> ids;
  std::vector<int> out(labels.plane_size());
  std::string key(labels.channels * sizeof(float), '\0');
  for (int y = 0; y < labels.height; ++y)
    for (int x = 0; x < labels.width; ++x) {
      bool white = true;
      for (int c = 0; c < labels.channels; ++c) {
        const float v = labels.at(c, x, y);
        white = white && v == 1.0f;
        std::memcpy(key.data() + c * sizeof(float), &v, sizeof(float));
      }
      const std::size_t k = static_cast<std::size_t>(y) * labels.width + x;
      if (white && !white_is_label) {
        out[k] = kUnknown;
        continue;
      }
      out[k] = ids.try_emplace(key, static_cast<int>(ids.size())).first->second;
    }
  *count = static_cast<int>(ids.size());
  return out;
}

class StitchGuidance final : public apps::ImageGuidance {
 public:
  StitchGuidance(const Image& composite, std::vector<int> ids, int labels, bool deramp)
      : ImageGuidance(composite, nullptr, 0.0, 1.0), ids_(std::move(ids)) {
    if (deramp) compute_ramps(labels);
  }

 protected:
  bool keep(int i, int j, int i2, int j2) const override {
    const int a = id(i, j);
    return a != kUnknown && a == id(i2, j2);
  }
  double offset(int c, int i, int j, bool horizontal) const override {
    if (ramp_.empty()) return 0.0;
    return ramp_[(static_cast<std::size_t>(id(i, j)) * src_.channels + c) * 2 + (horizontal ? 0 : 1)];
  }

 private:
  int id(int i, int j) const { return ids_[static_cast<std::size_t>(j) * src_.width + i]; }

  // Mean horizontal and vertical difference inside each label, per channel.
  void compute_ramps(int labels) {
    const int ch = src_.channels;
    std::vector<double> sum(static_cast<std::size_t>(labels) * ch * 2, 0.0), count(labels * 2, 0.0);
    for (int j = 0; j < src_.height; ++j)
      for (int i = 0; i < src_.width; ++i) {
        const int a = id(i, j);
        if (a == kUnknown) continue;
        for (int dir = 0; dir < 2; ++dir) {
          const int i2 = i + (dir == 0), j2 = j + (dir == 1);
          if (i2 >= src_.width || j2 >= src_.height || id(i2, j2) != a) continue;
          count[a * 2 + dir] += 1.0;
          for (int c = 0; c < ch; ++c)
            sum[(static_cast<std::size_t>(a) * ch + c) * 2 + dir] += double(src_.at(c, i2, j2)) - src_.at(c, i, j);
        }
      }
    ramp_.assign(sum.size(), 0.0);
    for (int a = 0; a < labels; ++a)
      for (int c = 0; c < ch; ++c)
        for (int dir = 0; dir < 2; ++dir) {
          const std::size_t k = (static_cast<std::size_t>(a) * ch + c) * 2 + dir;
          if (count[a * 2 + dir] > 0.0) ramp_[k] = sum[k] / count[a * 2 + dir];
        }
  }

  std::vector<int> ids_;
  std::vector<double> ramp_;
};

}  // namespace

Image stitch(const Image& composite, const Image& labels, const StitchOptions& options,
             const SolverOptions& solver, SolveSummary* summary) {
  if (composite.width != labels.width || composite.height != labels.height)
    throw InputError(fmt::format("label map is {}x{} but the composite is {}x{}", labels.width, labels.height,
                                 composite.width, composite.height));
  int count = 0;
  std::vector<int> ids = label_ids(labels, options.unknown == UnknownMode::Label, &count);
  std::vector<bool> known(ids.size());
  for (std::size_t k = 0; k < ids.size(); ++k) known[k] = ids[k] != kUnknown;
  StitchGuidance guidance(composite, std::move(ids), count, options.deramp);
  Image out = solve(guidance, solver, options.start_from_composite ? &composite : nullptr, summary);
  match_means(out, channel_means(composite, known), known);
  restore_non_finite(out, composite);
  if (options.unknown == UnknownMode::Black)
    for (int c = 0; c < out.channels; ++c)
      for (std::size_t k = 0; k < known.size(); ++k)
        if (!known[k]) out.plane(c)[k] = 0.0f;
  return out;
}

}  // namespace gdp
