// Layout helpers shared by the resampler's sources and targets (internal).
#pragma once

#include "gdp/sphere.h"

namespace gdp::sphere {

// Direction of face-local coordinates (x, y) of cube face `face` (0..5: +X, -X, +Y, -Y, +Z, -Z);
// outside [0, F]^2 it continues on the face's plane, which is what stencils across edges need.
Vec3 cube_face_direction(int face_size, int face, double x, double y);

}  // namespace gdp::sphere
