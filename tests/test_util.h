// Helpers shared by the tests: guidance from an image's exact gradients, dense operators.
#pragma once

#include <cmath>
#include <random>
#include <vector>

#include "gdp/guidance.h"
#include "gdp/image.h"
#include "gdp/topology.h"

namespace gdp::test {

// Guidance whose gradients are the exact differences of `image` (scaled by beta) and whose
// values are the image itself with weight alpha. Rows wrap around on periodic domains (x_edges
// says so); on spherical ones the edges across the top and bottom join mirrored pixels.
class ExactGradients : public GuidanceSource {
 public:
  ExactGradients(const Image& image, Domain domain, double alpha = 0.0, double beta = 1.0)
      : img_(image), alpha_(alpha), beta_(beta) {
    (void)domain;  // the solver tells rows apart (GuidanceRow::x_edges and spherical)
  }
  int width() const override { return img_.width; }
  int height() const override { return img_.height; }
  int channels() const override { return img_.channels; }
  double alpha() const override { return alpha_; }
  void read_row(int j, GuidanceRow& out) override {
    const int w = img_.width, e = out.x_edges;
    for (int c = 0; c < img_.channels; ++c) {
      for (int i = 0; i < e; ++i)
        out.gx[c * e + i] = beta_ * (double(img_.at(c, (i + 1) % w, j)) - img_.at(c, i, j));
      for (int i = 0; i < w; ++i) {
        const int h = img_.height;
        double below = 0.0;
        if (j + 1 < h) below = img_.at(c, i, j + 1);
        else if (out.spherical) below = img_.at(c, ((w / 2 - 1 - i) % w + w) % w, j);
        out.gy[c * w + i] = j + 1 < h || out.spherical ? beta_ * (below - img_.at(c, i, j)) : 0.0;
        if (out.spherical && j == 0)
          out.gy_above[c * w + i] = beta_ * (double(img_.at(c, i, 0)) - img_.at(c, w - 1 - i, 0));
        out.value[c * w + i] = img_.at(c, i, j);
      }
    }
  }

 private:
  const Image& img_;
  double alpha_, beta_;
};

inline Image random_image(int w, int h, int c, unsigned seed = 1) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> dist(0.0f, 1.0f);
  Image img(w, h, c);
  for (float& v : img.data) v = dist(rng);
  return img;
}

// A smooth image satisfying Neumann conditions: cos(pi kx (x+0.5)/w) cos(pi ky (y+0.5)/h).
inline Image cosine_image(int w, int h, int kx, int ky) {
  Image img(w, h, 1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      img.at(0, x, y) = static_cast<float>(std::cos(M_PI * kx * (x + 0.5) / w) * std::cos(M_PI * ky * (y + 0.5) / h));
  return img;
}

inline double rms_difference(const Image& a, const Image& b, int c = 0) {
  double s = 0.0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      const double d = double(a.at(c, x, y)) - b.at(c, x, y);
      s += d * d;
    }
  return std::sqrt(s / (double(a.width) * a.height));
}

// RMS difference over the first `channels` channels, each channel's mean difference removed
// (a blend is defined up to a constant level).
inline double rms_difference_mean_removed(const Image& out, const Image& truth, int channels = 3) {
  double total = 0.0;
  for (int c = 0; c < channels; ++c) {
    double s = 0.0, s2 = 0.0;
    for (int y = 0; y < truth.height; ++y)
      for (int x = 0; x < truth.width; ++x) {
        const double d = double(out.at(c, x, y)) - truth.at(c, x, y);
        s += d;
        s2 += d * d;
      }
    const double n = double(truth.width) * truth.height;
    total += s2 / n - (s / n) * (s / n);
  }
  return std::sqrt(total / channels);
}

inline double max_difference(const Image& a, const Image& b) {
  double m = 0.0;
  for (std::size_t k = 0; k < a.data.size(); ++k) m = std::max(m, std::abs(double(a.data[k]) - b.data[k]));
  return m;
}

inline double mean(const Image& a, int c = 0) {
  double s = 0.0;
  for (float v : a.plane(c)) s += v;
  return s / double(a.plane_size());
}

// a minus its mean, per channel (solutions of pure gradient problems are defined up to a constant).
inline Image zero_mean(Image a) {
  for (int c = 0; c < a.channels; ++c) {
    const double m = mean(a, c);
    for (float& v : a.plane(c)) v = static_cast<float>(v - m);
  }
  return a;
}

}  // namespace gdp::test
