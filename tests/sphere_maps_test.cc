// Sphere <-> square maps: TOAST test vectors, round trips, octants, edges, poles, equal area.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "gdp/errors.h"
#include "gdp/sphere.h"

namespace gdp::sphere {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

double lon_deg(const Vec3& p) {
  double l = std::atan2(p.y, p.x) / kDeg;
  return l < 0 ? l + 360.0 : l;
}
double lat_deg(const Vec3& p) { return std::atan2(p.z, std::hypot(p.x, p.y)) / kDeg; }
double dist(const Vec3& a, const Vec3& b) { return std::hypot(a.x - b.x, a.y - b.y, a.z - b.z); }
Vec3 unit(double x, double y, double z) {
  const double n = std::sqrt(x * x + y * y + z * z);
  return {x / n, y / n, z / n};
}

TEST(SphereMaps, ToastTestVectors) {
  const Vec3 p = toast_to_sphere(1.0 / 3.0, 1.0 / 3.0);
  EXPECT_LT(dist(p, unit(1, 1, 1)), 1e-15);
  const Vec3 q = toast_to_sphere(0.25, 0.25);
  EXPECT_NEAR(lon_deg(q), 45.0, 1e-12);
  EXPECT_NEAR(lat_deg(q), 54.7356, 1e-4);
  const Vec3 r = toast_to_sphere(0.75, 0.25);
  EXPECT_NEAR(lon_deg(r), 22.5, 1e-12);
  EXPECT_NEAR(lat_deg(r), 0.0, 1e-12);
  const Vec3 s = toast_to_sphere(-0.5, -0.25);
  EXPECT_NEAR(lon_deg(s), 206.5651, 1e-4);
  EXPECT_NEAR(lat_deg(s), 24.0948, 1e-4);
}

TEST(SphereMaps, ToastLandmarks) {
  // North pole at the centre, south pole at the corners, lon 0/90/180/270 at the edge midpoints.
  EXPECT_LT(dist(toast_to_sphere(0, 0), {0, 0, 1}), 1e-15);
  for (double s : {-1.0, 1.0})
    for (double t : {-1.0, 1.0}) EXPECT_LT(dist(toast_to_sphere(s, t), {0, 0, -1}), 1e-15);
  EXPECT_LT(dist(toast_to_sphere(1, 0), {1, 0, 0}), 1e-15);
  EXPECT_LT(dist(toast_to_sphere(0, 1), {0, 1, 0}), 1e-15);
  EXPECT_LT(dist(toast_to_sphere(-1, 0), {-1, 0, 0}), 1e-15);
  EXPECT_LT(dist(toast_to_sphere(0, -1), {0, -1, 0}), 1e-15);
  // The square's edges fold: (1, t) and (1, -t) are the same point (on the lon-0 meridian).
  for (double t : {0.1, 0.37, 0.8}) {
    EXPECT_LT(dist(toast_to_sphere(1, t), toast_to_sphere(1, -t)), 1e-15);
    EXPECT_NEAR(lon_deg(toast_to_sphere(1, t)), 0.0, 1e-12);
    EXPECT_LT(dist(toast_to_sphere(t, -1), toast_to_sphere(-t, -1)), 1e-15);
  }
  // The axes are meridians: uniform subdivision of great arcs, so latitude is linear in |s|.
  for (double a : {0.125, 0.3, 0.5, 0.9}) EXPECT_NEAR(lat_deg(toast_to_sphere(a, 0)), 90.0 * (1 - a), 1e-9);
}

void expect_round_trips(SquareMap map, double tol) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst = 0.0;
  for (int k = 0; k < 3000; ++k) {
    const double s = u(rng), t = u(rng);
    const Point2 back = square_from_sphere(map, square_to_sphere(map, s, t));
    worst = std::max({worst, std::abs(back.x - s), std::abs(back.y - t)});
  }
  EXPECT_LT(worst, tol);
  // Points on the sphere: forward(inverse(p)) == p (every octant, equator, near the poles).
  std::normal_distribution<double> g;
  for (int k = 0; k < 3000; ++k) {
    Vec3 p = unit(g(rng), g(rng), g(rng));
    if (k % 10 == 1) p = unit(p.x, p.y, 0.0);
    if (k % 10 == 2) p = unit(1e-7 * p.x, 1e-7 * p.y, p.z);
    const Point2 st = square_from_sphere(map, p);
    EXPECT_LT(dist(square_to_sphere(map, st.x, st.y), p), tol) << p.x << " " << p.y << " " << p.z;
  }
}

TEST(SphereMaps, ToastRoundTrip) { expect_round_trips(SquareMap::Toast, 1e-12); }
TEST(SphereMaps, OctahedralRoundTrip) { expect_round_trips(SquareMap::Octahedral, 1e-12); }

TEST(SphereMaps, InverseAtOctantEdgesAndPoles) {
  for (SquareMap map : {SquareMap::Toast, SquareMap::Octahedral}) {
    const Point2 n = square_from_sphere(map, {0, 0, 1});
    EXPECT_NEAR(n.x, 0.0, 1e-15);
    EXPECT_NEAR(n.y, 0.0, 1e-15);
    const Point2 s = square_from_sphere(map, {0, 0, -1});
    EXPECT_NEAR(std::abs(s.x), 1.0, 1e-15);
    EXPECT_NEAR(std::abs(s.y), 1.0, 1e-15);
    const Point2 x = square_from_sphere(map, {1, 0, 0});
    EXPECT_NEAR(x.x, 1.0, 1e-15);
    EXPECT_NEAR(x.y, 0.0, 1e-15);
    const Point2 y = square_from_sphere(map, {0, -1, 0});
    EXPECT_NEAR(y.x, 0.0, 1e-15);
    EXPECT_NEAR(y.y, -1.0, 1e-15);
    // Not only unit vectors.
    const Point2 a = square_from_sphere(map, {3, 3, 3}), b = square_from_sphere(map, unit(1, 1, 1));
    EXPECT_NEAR(a.x, b.x, 1e-15);
    EXPECT_NEAR(a.y, b.y, 1e-15);
  }
}

// Uniform random directions land uniformly on the square only for an equal-area map.
TEST(SphereMaps, OctahedralIsEqualArea) {
  std::mt19937 rng(3);
  std::normal_distribution<double> g;
  constexpr int kCells = 8, kPoints = 400000;
  std::vector<int> count(kCells * kCells, 0);
  for (int k = 0; k < kPoints; ++k) {
    const Point2 st = octahedral_from_sphere({g(rng), g(rng), g(rng)});
    const int cx = std::min(kCells - 1, static_cast<int>((st.x + 1) / 2 * kCells));
    const int cy = std::min(kCells - 1, static_cast<int>((st.y + 1) / 2 * kCells));
    ++count[cy * kCells + cx];
  }
  const double expected = double(kPoints) / (kCells * kCells);
  for (int c : count) EXPECT_NEAR(c, expected, 5.0 * std::sqrt(expected));  // 5 sigma
  // The Jacobian determinant is pi everywhere (4 units of square area onto 4 pi steradians).
  std::uniform_real_distribution<double> u(-0.999, 0.999);
  const double h = 1e-6;
  for (int k = 0; k < 500; ++k) {
    const double s = u(rng), t = u(rng);
    const Vec3 ds0 = octahedral_to_sphere(s + h, t), ds1 = octahedral_to_sphere(s - h, t);
    const Vec3 dt0 = octahedral_to_sphere(s, t + h), dt1 = octahedral_to_sphere(s, t - h);
    // Skip points whose stencil straddles a fold (axes or the equator diamond).
    if (std::abs(std::abs(s) + std::abs(t) - 1) < 3 * h || std::abs(s) < 3 * h || std::abs(t) < 3 * h) continue;
    const Vec3 a{(ds0.x - ds1.x) / (2 * h), (ds0.y - ds1.y) / (2 * h), (ds0.z - ds1.z) / (2 * h)};
    const Vec3 b{(dt0.x - dt1.x) / (2 * h), (dt0.y - dt1.y) / (2 * h), (dt0.z - dt1.z) / (2 * h)};
    const double area = std::hypot(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
    EXPECT_NEAR(area, std::numbers::pi, 1e-5 * std::numbers::pi);
  }
}

TEST(SphereMaps, ParseMapName) {
  EXPECT_EQ(parse_square_map("toast"), SquareMap::Toast);
  EXPECT_EQ(parse_square_map("octahedral"), SquareMap::Octahedral);
  EXPECT_THROW(parse_square_map("healpix"), UsageError);
}

}  // namespace
}  // namespace gdp::sphere
