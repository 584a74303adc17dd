// Small vector helpers for the sphere code (internal).
#pragma once

#include <cmath>

#include "gdp/sphere.h"

namespace gdp::sphere {

inline Vec3 operator+(const Vec3& a, const Vec3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3 operator-(const Vec3& a, const Vec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3 operator*(double k, const Vec3& a) { return {k * a.x, k * a.y, k * a.z}; }
inline double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }
inline Vec3 normalise(const Vec3& a) { return (1.0 / norm(a)) * a; }
// Normalised midpoint of two unit vectors: the point halving their great-circle arc.
inline Vec3 midpoint(const Vec3& a, const Vec3& b) { return normalise(a + b); }
// Angle between two vectors (stable for small and large angles).
inline double angle(const Vec3& a, const Vec3& b) { return std::atan2(norm(cross(a, b)), dot(a, b)); }
// det(a, b, p) computed from differences, accurate when the three are close together.
inline double orient(const Vec3& a, const Vec3& b, const Vec3& p) { return dot(cross(b - a, p - a), a); }

inline Vec3 rotate(const std::array<double, 9>& m, const Vec3& v) {
  return {m[0] * v.x + m[1] * v.y + m[2] * v.z, m[3] * v.x + m[4] * v.y + m[5] * v.z,
          m[6] * v.x + m[7] * v.y + m[8] * v.z};
}

}  // namespace gdp::sphere
