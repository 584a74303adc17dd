// Smooth plate backgrounds from the overlaps: offset + plane + radial term per plate, the minimum-norm fit where overlaps cannot tell.
#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "sky/overlap_samples.h"
#include "sky/plate.h"

namespace gdp::sky {

// A plate's background: offset + u * slope_u + v * slope_v + radial * (u^2 + v^2 - mean), u and v
// the plate's pixel coordinates about its centre in units of its longer side (background_basis).
struct PlateBackground {
  double offset = 0, slope_u = 0, slope_v = 0, radial = 0;
};

// The model's four basis functions at pixel (x, y) of `plate` (gdp pixel coordinates): 1, u, v,
// u^2 + v^2 less its mean over the plate's rectangle, with u = (x - width/2) / L, v = (y -
// height/2) / L, L = max(width, height). The last three have mean zero over the plate.
std::array<double, 4> background_basis(const Plate& plate, double x, double y);
// The same for any rectangle of width x height pixels (gdp sky --projected: an image on the template).
std::array<double, 4> background_basis(double width, double height, double x, double y);

// One sample of a difference between two plates: b's basis enters with a minus sign.
struct BackgroundEquation {
  int a = 0, b = 0;
  std::array<double, 4> basis_a{}, basis_b{};
  double difference = 0;  // a's value minus b's
};

// The mean square of each basis function over the plate's rectangle (1 for the offset): a
// background's energy is sum_i energy_i c_i^2 (the basis is orthogonal over the rectangle).
std::array<double, 4> background_energy(const Plate& plate);
std::array<double, 4> background_energy(double width, double height);

// Backgrounds of the plates (energy: background_energy of each) minimising
//   sum over equations (B_a(p) - B_b(p) - difference)^2 + lambda sum over plates (energy of the smooth terms),
// lambda = damping x the equations' normal matrix's smooth diagonal per unit of energy. Differences
// do not see a background common to all plates (a constant, a plane and a bowl over the whole
// mosaic fit every plate's model): the damping picks, among the fits, the one whose smooth
// backgrounds have the least energy, so the common part is left where it was. Offsets are not
// damped; they come out with mean 0 over the plates in some equation. Robust: after the
// least-squares fit, a few iterations reweight the equations by Huber's rule (weight 1 within
// 3 robust spreads of the residuals, less beyond), so that stars and defects in the overlaps
// do not pull the fit (`robust` false: plain least squares). Eigen's conjugate gradients on the block-sparse normal equations.
// `equations(visit)` calls visit on every equation, in the same order each time (it is called
// once per pass: the least-squares fit, then two per reweighting; the equations need not be in
// memory: overlap_store.h). Memory: 8 bytes per equation (the residuals' median) and the normal
// equations (16 numbers per plate and per overlapping pair).
using BackgroundEquations = std::function<void(const std::function<void(const BackgroundEquation&)>&)>;
std::vector<PlateBackground> fit_backgrounds(const std::vector<std::array<double, 4>>& energy,
                                             const BackgroundEquations& equations, double damping, bool robust = true);

// The equation of one overlap sample of plates a and b (indices ia and ib; overlap_samples(a, b)).
BackgroundEquation background_equation(const Plate& a, int ia, const Plate& b, int ib, const OverlapSample& s);

// The equations of the plates' overlaps, all plates in memory, and their fit. Uses the plates'
// WCS (not thread-safe). gdp sky streams the plates instead (plate_passes.h).
std::vector<PlateBackground> plate_backgrounds(const std::vector<Plate>& plates, double damping, bool robust = true);

// The rms over the plate of the background's smooth terms (plane and radial; not the offset).
double smooth_rms(const Plate& plate, const PlateBackground& background);
double smooth_rms(double width, double height, const PlateBackground& background);

// One line for the user: how many plates' backgrounds were fitted, the median of their smooth
// terms' rms and the largest three, with the plates' file names.
std::string backgrounds_note(const std::vector<std::string>& paths, const std::vector<double>& rms);

// Subtracts the plate's smooth terms (not its offset: the solve removes constants exactly) from
// its pixels, and from its mean.
void subtract_smooth_background(Plate& plate, const PlateBackground& background);

}  // namespace gdp::sky
