// The row kernels (multigrid/row_kernels.h) give, bit for bit, what their plain scalar definitions give.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "multigrid/row_kernels.h"

namespace gdp::multigrid {
namespace {

// Random samples with the values that masks get wrong first: NaN, infinities, -0.0.
std::vector<float> samples(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> uniform(-2.0f, 2.0f);
  const float special[] = {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                           -std::numeric_limits<float>::infinity(), -0.0f, 0.0f};
  std::vector<float> v(n);
  for (int i = 0; i < n; ++i) v[i] = rng() % 7 == 0 ? special[rng() % 5] : uniform(rng);
  return v;
}

// Doubles with all 53 bits used (products of them are not exact, so a fused multiply-add would show).
std::vector<double> doubles(int n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(-2.0, 2.0);
  std::vector<double> v(n);
  for (double& x : v) x = uniform(rng);
  if (n > 2) v[2] = -0.0;
  return v;
}

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

// Lengths that leave every tail of the vector loops.
constexpr int kLengths[] = {1, 3, 7, 8, 9, 31, 37, 1000};

TEST(RowKernels, KeptDifferencesAreTheScalarOnes) {
  for (const int n : kLengths) {
    const std::vector<float> from = samples(n, 1), to = samples(n, 2);
    std::vector<unsigned char> keep(n);
    for (int i = 0; i < n; ++i) keep[i] = static_cast<unsigned char>(i % 3);  // 0, 1 and 2 (set, not 1)
    for (const double beta : {1.0, 0.5, -3.0}) {
      std::vector<double> got(n), want(n);
      kept_differences(from.data(), to.data(), keep.data(), beta, got.data(), n);
      for (int i = 0; i < n; ++i) {
        const double d = double(to[i]) - from[i];
        want[i] = keep[i] != 0 && std::isfinite(d) ? beta * d : 0.0;
      }
      EXPECT_TRUE(same_bits(got, want)) << "n " << n << ", beta " << beta;
    }
  }
}

template <class T>
void check_guess_and_weights() {
  const int channels = 3;
  for (const int n : kLengths) {
    const int stride = n + 5;  // planes apart by more than the row
    const std::vector<float> in = samples(channels * stride, 3);
    std::vector<unsigned char> counted(n);
    for (int i = 0; i < n; ++i) counted[i] = i % 5 != 0;
    std::vector<T> u(channels * stride, T(7)), w(n), want_u = u, want_w(n);
    guess_and_weights(in.data(), stride, channels, counted.data(), u.data(), w.data(), n);
    for (int i = 0; i < n; ++i) {
      bool known = counted[i] != 0;
      for (int c = 0; c < channels; ++c) {
        const float v = in[c * stride + i];
        known = known && std::isfinite(v);
        want_u[c * stride + i] = std::isfinite(v) ? static_cast<T>(v) : T(0);
      }
      want_w[i] = known ? T(1) : T(0);
    }
    EXPECT_TRUE(same_bits(u, want_u)) << "n " << n;  // samples between the planes left as they were
    EXPECT_TRUE(same_bits(w, want_w)) << "n " << n;
  }
}

TEST(RowKernels, GuessAndWeightsAreTheScalarOnes) {
  check_guess_and_weights<float>();
  check_guess_and_weights<double>();
}

template <class T>
void check_scaled_rhs() {
  for (const int n : kLengths) {
    const std::vector<double> v = doubles(n, 4), add = doubles(n, 5);
    std::vector<T> got(n), got_plain(n), want(n), want_plain(n);
    scaled_rhs(v.data(), add.data(), 720.0, got.data(), n);
    scaled_rhs(v.data(), nullptr, 720.0, got_plain.data(), n);
    for (int i = 0; i < n; ++i) {
      volatile double product = 720.0 * v[i];  // not contracted into a multiply-add here either
      want[i] = static_cast<T>(product + add[i]);
      want_plain[i] = static_cast<T>(product + 0.0);  // -0.0 becomes +0.0
    }
    EXPECT_TRUE(same_bits(got, want)) << "n " << n;
    EXPECT_TRUE(same_bits(got_plain, want_plain)) << "n " << n;
  }
}

TEST(RowKernels, ScaledRightHandSidesAreTheScalarOnes) {
  check_scaled_rhs<float>();
  check_scaled_rhs<double>();
  const double negative_zero = -0.0;
  float out = -1.0f;
  scaled_rhs(&negative_zero, nullptr, 720.0, &out, 1);
  EXPECT_FALSE(std::signbit(out));  // as the sum with a zero row always gave
}

TEST(RowKernels, RowDotSumsInEightLanesInColumnOrder) {
  for (const int n : kLengths) {
    const std::vector<float> w = samples(n, 6), u = samples(n, 7);
    std::vector<float> wf(w), uf(u);
    for (float& x : wf) x = std::isfinite(x) ? x : 1.0f;  // finite sums: NaN has no bits to compare
    for (float& x : uf) x = std::isfinite(x) ? x : 0.25f;
    double lane[8] = {};
    for (int i = 0; i < n; ++i) {
      volatile double product = static_cast<double>(wf[i]) * uf[i];
      lane[i % 8] += product;
    }
    const double want = ((lane[0] + lane[4]) + (lane[1] + lane[5])) + ((lane[2] + lane[6]) + (lane[3] + lane[7]));
    const double got = row_dot(wf.data(), uf.data(), n);
    EXPECT_EQ(std::memcmp(&got, &want, sizeof got), 0) << "n " << n << ": " << got << " against " << want;
    const std::vector<double> wd = doubles(n, 8), ud = doubles(n, 9);
    double lane_double[8] = {};
    for (int i = 0; i < n; ++i) {
      volatile double product = wd[i] * ud[i];
      lane_double[i % 8] += product;
    }
    const double want_double = ((lane_double[0] + lane_double[4]) + (lane_double[1] + lane_double[5])) +
                               ((lane_double[2] + lane_double[6]) + (lane_double[3] + lane_double[7]));
    const double got_double = row_dot(wd.data(), ud.data(), n);
    EXPECT_EQ(std::memcmp(&got_double, &want_double, sizeof got), 0) << "n " << n;
  }
}

// row_squares is row_dot(r, r) bit for bit (every length's tail included), and the sum of squares in long
// double to rounding; infinities and NaN come through as row_dot gives them.
template <class T>
void check_row_squares() {
  for (const int n : kLengths) {
    const std::vector<double> d = doubles(n, 12);
    const std::vector<T> r(d.begin(), d.end());
    const double got = row_squares(r.data(), n), want = row_dot(r.data(), r.data(), n);
    EXPECT_EQ(std::memcmp(&got, &want, sizeof got), 0) << "n " << n << ": " << got << " against " << want;
    long double exact = 0;
    for (T v : r) exact += static_cast<long double>(v) * v;
    EXPECT_NEAR(got, static_cast<double>(exact), 1e-14 * static_cast<double>(exact) + 1e-300) << "n " << n;
  }
  const T special[] = {T(1), std::numeric_limits<T>::infinity(), T(2), std::numeric_limits<T>::quiet_NaN()};
  EXPECT_EQ(row_squares(special, 3), std::numeric_limits<double>::infinity());
  EXPECT_TRUE(std::isnan(row_squares(special, 4)));
}

TEST(RowKernels, RowSquaresIsRowDotOfARowWithItself) {
  check_row_squares<float>();
  check_row_squares<double>();
}

}  // namespace
}  // namespace gdp::multigrid
