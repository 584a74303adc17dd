// Equirectangular and cube-map pixel coordinates <-> directions.
#include <cmath>
#include <numbers>

#include "sphere/layouts.h"
#include "sphere/vec3.h"

namespace gdp::sphere {

namespace {
constexpr double kPi = std::numbers::pi;
}

Vec3 equirect_direction(int width, int height, double x, double y, bool sky) {
  double lon = 2.0 * kPi * x / width - kPi;
  if (sky) lon = -lon;
  const double lat = 0.5 * kPi - kPi * y / height;
  const double c = std::cos(lat);
  return {c * std::cos(lon), c * std::sin(lon), std::sin(lat)};
}

Point2 equirect_from_direction(int width, int height, const Vec3& p, bool sky) {
  double lon = std::atan2(p.y, p.x);
  if (sky) lon = -lon;
  const double lat = std::atan2(p.z, std::hypot(p.x, p.y));
  double x = (lon + kPi) / (2.0 * kPi) * width;
  if (x >= width) x -= width;
  if (x < 0) x += width;
  return {x, (0.5 * kPi - lat) / kPi * height};
}

// Faces in OpenEXR's frame (X, Y, Z) = (-y, z, x). Face k's pixel (u, v) in [0, 1]^2 (u right,
// v down) sees the OpenEXR direction given by ImfEnvmap's pixelPosition(): +X: (1, 1-2v, 2u-1),
// -X: (-1, 1-2v, 1-2u), +Y: (2u-1, 1, 1-2v), -Y: (2u-1, -1, 2v-1), +Z: (1-2u, 1-2v, 1),
// -Z: (2u-1, 1-2v, -1).
Vec3 cube_face_direction(int face_size, int face, double x, double y) {
  const double u = 2.0 * x / face_size - 1.0;  // -1 .. 1, right (beyond: the face's plane extended)
  const double v = 1.0 - 2.0 * y / face_size;  // -1 .. 1, up
  Vec3 e;  // OpenEXR frame
  switch (face) {
    case 0: e = {1.0, v, u}; break;
    case 1: e = {-1.0, v, -u}; break;
    case 2: e = {u, 1.0, v}; break;
    case 3: e = {u, -1.0, -v}; break;
    case 4: e = {-u, v, 1.0}; break;
    default: e = {u, v, -1.0}; break;
  }
  return normalise(Vec3{e.z, -e.x, e.y});
}

Vec3 cube_direction(int face_size, double x, double y) {
  const int face = std::min(5, std::max(0, static_cast<int>(std::floor(y / face_size))));
  return cube_face_direction(face_size, face, x, y - double(face) * face_size);
}

Point2 cube_from_direction(int face_size, const Vec3& p) {
  const Vec3 e{-p.y, p.z, p.x};
  const double ax = std::abs(e.x), ay = std::abs(e.y), az = std::abs(e.z);
  int face = 0;
  double u = 0.0, v = 0.0;
  if (ax >= ay && ax >= az) {
    face = e.x > 0 ? 0 : 1;
    u = (e.x > 0 ? e.z : -e.z) / ax;
    v = e.y / ax;
  } else if (ay >= az) {
    face = e.y > 0 ? 2 : 3;
    u = e.x / ay;
    v = (e.y > 0 ? e.z : -e.z) / ay;
  } else {
    face = e.z > 0 ? 4 : 5;
    u = (e.z > 0 ? -e.x : e.x) / az;
    v = e.y / az;
  }
  const double f = face_size;
  const double x = std::min(f, std::max(0.0, (u + 1.0) * 0.5 * f));
  const double y = std::min(f, std::max(0.0, (1.0 - v) * 0.5 * f));
  return {x, face * f + y};
}

}  // namespace gdp::sphere
