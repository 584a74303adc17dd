// Reproduces the paper's Table I: rebuild a spherical image from its own gradients, error after 1..N V-cycles.
//
// Usage: sphere_table1 EQUIRECT_IMAGE [--height H=512] [--pq-height P] [--sweeps K=3] [--cycles N=4]
//                      [--coarsest C=32]
// The 2:1 equirectangular source is box-filtered to 2H x H (integer factors) for the ER rows and
// resampled by gdp::sphere::resample to a TOAST PQ image 4P x P for the PQ rows (P defaults to
// sphere::default_pq_height of the ER pixel count). Values as read ([0, 1] for 8-bit files).
//   ER    the intrinsic equirectangular solver (src/sphere_eval), gradients measured on the sphere;
//   flat  control: the same solver and grid with the metric of a flat periodic rectangle (cos φ = 1);
//   PQ    gdp's solver on the Spherical domain, gradients in the parameter domain, read in double;
//   PQ'   the same through gdp::reconstruct, whose float output rounds errors below ~1e-8 away.
// Every run is double precision from a zero start; errors are taken against the image the solver
// was given, after removing each channel's mean difference, over all samples of all channels.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "apps/image_guidance.h"
#include "gdp/apps.h"
#include "gdp/errors.h"
#include "gdp/image.h"
#include "gdp/image_io.h"
#include "gdp/rows.h"
#include "gdp/solver.h"
#include "gdp/sphere.h"
#include "multigrid/incore_vcycle.h"
#include "multigrid/input_rows.h"
#include "schedule/solve_parts.h"
#include "sphere_eval/equirect_solver.h"

using namespace gdp;

namespace {

struct Args {
  std::string image;
  int height = 512, pq_height = 0, sweeps = 3, cycles = 4, coarsest = 32;
};

Args parse(int argc, char** argv) {
  Args a;
  for (int k = 1; k < argc; ++k) {
    const std::string s = argv[k];
    auto next = [&]() { return k + 1 < argc ? std::atoi(argv[++k]) : -1; };
    if (s == "--height") a.height = next();
    else if (s == "--pq-height") a.pq_height = next();
    else if (s == "--sweeps") a.sweeps = next();
    else if (s == "--cycles") a.cycles = next();
    else if (s == "--coarsest") a.coarsest = next();
    else a.image = s;
  }
  return a;
}

// Averages blocks of fx x fy pixels (the image's size must be a multiple of the target's).
Image box_downsample(const Image& in, int w, int h) {
  if (in.width % w != 0 || in.height % h != 0)
    throw UsageError(std::to_string(in.width) + "x" + std::to_string(in.height) + " is not a multiple of " +
                     std::to_string(w) + "x" + std::to_string(h));
  const int fx = in.width / w, fy = in.height / h;
  Image out(w, h, in.channels);
  for (int c = 0; c < in.channels; ++c)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        double s = 0.0;
        for (int dy = 0; dy < fy; ++dy)
          for (int dx = 0; dx < fx; ++dx) s += in.at(c, x * fx + dx, y * fy + dy);
        out.at(c, x, y) = static_cast<float>(s / (fx * fy));
      }
  return out;
}

// Errors of solutions against originals after removing each channel's mean difference.
struct ErrorSums {
  double sum_sq = 0.0, max = 0.0, count = 0.0;
  void add(std::span<const double> u, std::span<const float> p) {
    double mean = 0.0;
    for (std::size_t k = 0; k < u.size(); ++k) mean += u[k] - p[k];
    mean /= static_cast<double>(u.size());
    for (std::size_t k = 0; k < u.size(); ++k) {
      const double e = std::abs(u[k] - mean - p[k]);
      sum_sq += e * e, max = std::max(max, e), count += 1.0;
    }
  }
  double rms() const { return std::sqrt(sum_sq / count); }
};

// One solver's rows of the table.
struct Rows {
  std::vector<ErrorSums> err;
  std::vector<double> residual;  // worst channel's |b - L u| / |b| after each cycle
  double seconds = 0.0;          // solving, all channels and cycles
  explicit Rows(int cycles) : err(cycles), residual(cycles, 0.0) {}
};

void print_rows(const char* name, const Rows& r, bool with_residual = true) {
  const auto line = [&](const char* what, auto value) {
    std::printf("%-5s %-5s", name, what);
    for (std::size_t n = 0; n < r.err.size(); ++n) std::printf("  %9.2e", value(n));
    std::printf("\n");
  };
  line("rms", [&](std::size_t n) { return r.err[n].rms(); });
  line("max", [&](std::size_t n) { return r.err[n].max; });
  if (with_residual) line("resid", [&](std::size_t n) { return r.residual[n]; });
}

double since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The intrinsic solver (or, with `flat`, its control): per channel b = L p, V-cycles from zero.
// On the sphere b is assembled from the image's spherical gradients (equal to L p, tested).
Rows equirect_rows(const Image& img, const Args& a, bool flat) {
  sphere_eval::EquirectSolverOptions opt;
  opt.sweeps = a.sweeps;
  opt.coarsest_height = a.coarsest;
  sphere_eval::EquirectOperator op = sphere_eval::EquirectOperator::make(img.width, img.height);
  if (flat) {  // Δλ = Δθ: unit weights, no flux through the top and bottom edges
    op.wx.assign(op.height, 1.0);
    op.wy.assign(op.height + 1, 1.0);
    op.wy.front() = op.wy.back() = 0.0;
  }
  const sphere_eval::EquirectSolver solver(op, opt);
  Rows rows(a.cycles);
  for (int c = 0; c < img.channels; ++c) {
    const auto plane = img.plane(c);
    const std::vector<double> p(plane.begin(), plane.end());
    std::vector<double> b(p.size());
    if (flat) op.apply(p, b);
    else b = sphere_eval::divergence_rhs(op, sphere_eval::spherical_gradients(op, p));
    std::vector<double> u(p.size(), 0.0);
    for (int n = 0; n < a.cycles; ++n) {
      const auto t0 = std::chrono::steady_clock::now();
      solver.vcycle(u, b);
      rows.seconds += since(t0);
      rows.err[n].add(u, plane);
      rows.residual[n] = std::max(rows.residual[n], solver.relative_residual(u, b));
    }
  }
  const auto& coarsest = solver.level(solver.levels() - 1);
  std::printf("%s: %dx%d, %d levels (coarsest %dx%d), %d sweeps, %.3f s per V-cycle per channel\n",
              flat ? "flat" : "ER", img.width, img.height, solver.levels(), coarsest.width(), coarsest.height(),
              a.sweeps, rows.seconds / (a.cycles * img.channels));
  return rows;
}

// gdp's solver on the Spherical domain, set up exactly as gdp::reconstruct with Precision::Float64
// and the in-core schedule (the image's own differences as guidance, zero start, the
// double-precision V-cycle), but with the solution read in double.
Rows pq_rows(const Image& pq, const Args& a) {
  SolverOptions opt;
  opt.domain = Domain::Spherical;
  opt.precision = Precision::Float64;
  opt.schedule = Schedule::InCore;
  opt.sweeps = opt.post_sweeps = a.sweeps;
  ImageRowReader reader(pq);
  apps::ImageGuidance guidance(reader, 0.0, 1.0, /*start_from_source=*/false);
  SolveSummary summary;
  const schedule::Problem<double> problem(guidance, opt, summary);
  multigrid::InputRows<double> input(guidance, problem.hierarchy);
  const int w = pq.width, h = pq.height, channels = pq.channels;
  std::vector<multigrid::Plane<double>> u(channels, {w, h}), b(channels, {w, h});
  {
    const std::size_t n = static_cast<std::size_t>(channels) * w;
    std::vector<double> ur(n), br(n), wr(w);
    for (int j = 0; j < h; ++j) {
      input.next(ur, br, wr);
      for (int c = 0; c < channels; ++c) {
        std::copy_n(ur.begin() + std::ptrdiff_t{c} * w, w, u[c].row(j));
        std::copy_n(br.begin() + std::ptrdiff_t{c} * w, w, b[c].row(j));
      }
    }
  }
  multigrid::InCoreVCycle<double> vc(problem.ops, opt.sweeps, opt.coarse_tolerance);
  Rows rows(a.cycles);
  for (int c = 0; c < channels; ++c) {
    const double b_norm = vc.residual_norm(u[c], b[c]);  // u starts at zero
    for (int n = 0; n < a.cycles; ++n) {
      const auto t0 = std::chrono::steady_clock::now();
      vc.run(u[c], b[c]);
      rows.seconds += since(t0);
      rows.err[n].add(u[c].data, pq.plane(c));
      rows.residual[n] = std::max(rows.residual[n], vc.residual_norm(u[c], b[c]) / b_norm);
    }
  }
  std::printf("PQ: %dx%d, %d levels (coarsest %dx%d), %d sweeps, %.3f s per V-cycle per channel\n", w, h,
              summary.levels, summary.level_widths.back(), summary.level_heights.back(), a.sweeps,
              rows.seconds / (a.cycles * channels));
  return rows;
}

// The public entry point gdp::reconstruct, one run per cycle count: agrees with pq_rows until
// its float output rounds the remaining error away.
Rows pq_public_rows(const Image& pq, const Args& a) {
  Rows rows(a.cycles);
  for (int n = 1; n <= a.cycles; ++n) {
    SolverOptions opt;
    opt.domain = Domain::Spherical;
    opt.precision = Precision::Float64;
    opt.sweeps = opt.post_sweeps = a.sweeps;
    opt.vcycles = n;
    const Image out = reconstruct(pq, opt).image;
    for (int c = 0; c < pq.channels; ++c) {
      const auto o = out.plane(c);
      rows.err[n - 1].add(std::vector<double>(o.begin(), o.end()), pq.plane(c));
    }
  }
  return rows;
}

}  // namespace

int main(int argc, char** argv) {
  Args a = parse(argc, argv);
  if (a.image.empty() || a.height < 1 || a.pq_height < 0 || a.cycles < 1) {
    std::fprintf(stderr,
                 "usage: %s EQUIRECT_IMAGE [--height H] [--pq-height P] [--sweeps K] [--cycles N] [--coarsest C]\n",
                 argv[0]);
    return 2;
  }
  try {
    const Image source = read_image(a.image).image;
    const Image er = box_downsample(source, 2 * a.height, a.height);
    if (a.pq_height == 0) a.pq_height = sphere::default_pq_height(static_cast<long long>(er.width) * er.height);
    const sphere::Projection from{sphere::Layout::Equirect}, to{sphere::Layout::Pq, sphere::SquareMap::Toast};
    const Image pq = sphere::resample(source, from, to, 4 * a.pq_height, a.pq_height);
    std::printf("%s (%dx%d) -> ER %dx%d, PQ %dx%d (TOAST), %d channels\n", a.image.c_str(), source.width,
                source.height, er.width, er.height, pq.width, pq.height, er.channels);
    const Rows er_rows = equirect_rows(er, a, false);
    const Rows flat_rows = equirect_rows(er, a, true);
    const Rows pq_rows_double = pq_rows(pq, a);
    const Rows pq_rows_public = pq_public_rows(pq, a);
    std::printf("\nV-cycles   ");
    for (int n = 1; n <= a.cycles; ++n) std::printf("  %9d", n);
    std::printf("\n");
    print_rows("ER", er_rows);
    print_rows("PQ", pq_rows_double);
    print_rows("PQ'", pq_rows_public, false);
    print_rows("flat", flat_rows);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
  return 0;
}
