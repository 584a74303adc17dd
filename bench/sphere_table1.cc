// Reproduces the paper's Table I: rebuild a spherical image from its own gradients, error after 1..N V-cycles.
//
// Usage: sphere_table1 EQUIRECT_IMAGE [--height H=512] [--sweeps K=3] [--cycles N=4] [--coarsest C=32]
// The 2:1 equirectangular image is box-filtered to 2H x H (integer factors), values as read ([0, 1]
// for 8-bit files). ER: the intrinsic equirectangular solver (src/sphere_eval), gradients measured
// on the sphere. Every figure is double precision from a zero start; errors are taken against the
// original after removing each channel's mean difference, over all samples of all channels.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "apps/image_guidance.h"
#include "gdp/apps.h"
#include "gdp/image.h"
#include "gdp/image_io.h"
#include "gdp/rows.h"
#include "gdp/solver.h"
#include "multigrid/incore_vcycle.h"
#include "schedule/input_rows.h"
#include "schedule/solve_parts.h"
#include "sphere_eval/equirect_solver.h"

using namespace gdp;

namespace {

struct Args {
  std::string image;
  int height = 512, pq_height = 512, sweeps = 3, cycles = 4, coarsest = 32;
};

Args parse(int argc, char** argv) {
  Args a;
  for (int k = 1; k < argc; ++k) {
    const std::string s = argv[k];
    auto next = [&]() { return k + 1 < argc ? std::atoi(argv[++k]) : 0; };
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
  if (in.width % w != 0 || in.height % h != 0) {
    std::fprintf(stderr, "%dx%d is not a multiple of %dx%d\n", in.width, in.height, w, h);
    std::exit(2);
  }
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

// Errors of one channel's solution against the original after removing the mean difference.
struct ErrorSums {
  double sum_sq = 0.0, max = 0.0, count = 0.0;
  void add(const std::vector<double>& u, const std::vector<double>& p) {
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

void print_row(const char* name, const char* what, const std::vector<double>& v) {
  std::printf("%-4s %-5s", name, what);
  for (double x : v) std::printf("  %9.2e", x);
  std::printf("\n");
}

// The ER rows: per channel, b = L p from the spherical gradients, then V-cycles from zero.
void equirect_rows(const Image& img, const Args& a) {
  sphere_eval::EquirectSolverOptions opt;
  opt.sweeps = a.sweeps;
  opt.coarsest_height = a.coarsest;
  const sphere_eval::EquirectSolver solver(img.width, img.height, 0.0, opt);
  const auto& op = solver.fine();
  std::vector<ErrorSums> err(a.cycles);
  std::vector<double> worst_residual(a.cycles, 0.0);
  double seconds = 0.0;
  for (int c = 0; c < img.channels; ++c) {
    const auto plane = img.plane(c);
    const std::vector<double> p(plane.begin(), plane.end());
    const std::vector<double> b = sphere_eval::divergence_rhs(op, sphere_eval::spherical_gradients(op, p));
    std::vector<double> u(p.size(), 0.0);
    for (int n = 0; n < a.cycles; ++n) {
      const auto t0 = std::chrono::steady_clock::now();
      solver.vcycle(u, b);
      seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      err[n].add(u, p);
      worst_residual[n] = std::max(worst_residual[n], solver.relative_residual(u, b));
    }
  }
  std::vector<double> rms, mx;
  for (const auto& e : err) rms.push_back(e.rms()), mx.push_back(e.max);
  std::printf("ER: %dx%d, %d levels (coarsest %dx%d), %d sweeps, %.2f s per V-cycle per channel\n", img.width,
              img.height, solver.levels(), solver.level(solver.levels() - 1).width(), solver.level(solver.levels() - 1).height(),
              a.sweeps, seconds / (a.cycles * img.channels));
  print_row("ER", "rms", rms);
  print_row("ER", "max", mx);
  print_row("ER", "resid", worst_residual);
}

// The PQ rows: gdp's own solver on the Spherical domain, set up exactly as gdp::reconstruct with
// Precision::Float64 and the in-core schedule (the image's own differences as guidance, zero
// start, the double-precision V-cycle), but reading the solution in double: gdp::reconstruct
// rounds its output to float, which would floor the error at ~1e-8.
void pq_rows(const Image& pq, const Args& a) {
  SolverOptions opt;
  opt.domain = Domain::Spherical;
  opt.precision = Precision::Float64;
  opt.schedule = Schedule::InCore;
  opt.sweeps = a.sweeps;
  ImageRowReader reader(pq);
  apps::ImageGuidance guidance(reader, 0.0, 1.0, /*start_from_source=*/false);
  SolveSummary summary;
  const schedule::Problem<double> problem(guidance, opt, summary);
  schedule::InputRows<double> input(guidance, problem.hierarchy);
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
  std::vector<ErrorSums> err(a.cycles);
  std::vector<double> worst_residual(a.cycles, 0.0);
  double seconds = 0.0;
  for (int c = 0; c < channels; ++c) {
    const auto plane = pq.plane(c);
    const std::vector<double> p(plane.begin(), plane.end());
    const double b_norm = vc.residual_norm(u[c], b[c]);  // u starts at zero
    for (int n = 0; n < a.cycles; ++n) {
      const auto t0 = std::chrono::steady_clock::now();
      vc.run(u[c], b[c]);
      seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      err[n].add(u[c].data, p);
      worst_residual[n] = std::max(worst_residual[n], vc.residual_norm(u[c], b[c]) / b_norm);
    }
  }
  std::vector<double> rms, mx;
  for (const auto& e : err) rms.push_back(e.rms()), mx.push_back(e.max);
  std::printf("PQ: %dx%d, %d levels (coarsest %dx%d), %d sweeps, %.2f s per V-cycle per channel\n", w, h,
              summary.levels, summary.level_widths.back(), summary.level_heights.back(), a.sweeps,
              seconds / (a.cycles * channels));
  print_row("PQ", "rms", rms);
  print_row("PQ", "max", mx);
  print_row("PQ", "resid", worst_residual);
}

// Cross-check through the public entry point gdp::reconstruct (same solver, float output): it
// must agree with pq_rows until float rounding (~1e-8) dominates.
void pq_public_rows(const Image& pq, const Args& a) {
  std::vector<double> rms, mx;
  for (int n = 1; n <= a.cycles; ++n) {
    SolverOptions opt;
    opt.domain = Domain::Spherical;
    opt.precision = Precision::Float64;
    opt.sweeps = a.sweeps;
    opt.vcycles = n;
    const Image out = reconstruct(pq, opt).image;
    ErrorSums e;
    for (int c = 0; c < pq.channels; ++c) {
      const auto o = out.plane(c), p = pq.plane(c);
      e.add(std::vector<double>(o.begin(), o.end()), std::vector<double>(p.begin(), p.end()));
    }
    rms.push_back(e.rms()), mx.push_back(e.max);
  }
  print_row("PQ'", "rms", rms);
  print_row("PQ'", "max", mx);
}

}  // namespace

int main(int argc, char** argv) {
  const Args a = parse(argc, argv);
  if (a.image.empty() || a.height < 1 || a.cycles < 1) {
    std::fprintf(stderr, "usage: %s EQUIRECT_IMAGE [--height H] [--sweeps K] [--cycles N] [--coarsest C]\n", argv[0]);
    return 2;
  }
  try {
    const Image img = box_downsample(read_image(a.image).image, 2 * a.height, a.height);
    std::printf("%s -> %dx%d, %d channels\n", a.image.c_str(), img.width, img.height, img.channels);
    std::printf("V-cycles  ");
    for (int n = 1; n <= a.cycles; ++n) std::printf("  %9d", n);
    std::printf("\n");
    equirect_rows(img, a);
    if (std::getenv("SPHERE_TABLE1_FAKE_PQ"))  // TEMPORARY: exercise the PQ path before the resampler exists
      pq_rows(box_downsample(read_image(a.image).image, 4 * a.pq_height, a.pq_height), a),
      pq_public_rows(box_downsample(read_image(a.image).image, 4 * a.pq_height, a.pq_height), a);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
  return 0;
}
