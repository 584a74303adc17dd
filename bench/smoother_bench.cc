// Convergence and CPU per V-cycle against the smoother: sweeps before/after the coarse correction, row direction.
//
// Usage: smoother_bench [SIZE=2048] [CYCLES=4] [PHOTO or -] [CONFIGS]
// In core, planar, alpha = 0 (the stitch's operator), one channel, from a zero guess. Two problems:
//   random: b uniform in [-1, 1] less its mean (every frequency at once);
//   manufactured: u* = the PHOTO's first channel cropped to SIZE (without one: smooth waves plus
//   piecewise-constant offsets in Voronoi cells, a stitch's kind of jumps), b = A u*.
// Per smoother: float CPU seconds of one V-cycle (thread CPU clock, the minimum of CYCLES) and Mpix/s of the
// one channel (an RGB V-cycle's figure, as vcycle_bench gives it, is a third of that);
// in double (the same arithmetic, no float floor) the residual reduction of each V-cycle and, for the
// manufactured problem, the RMS error against u* (each mean removed) after cycles 1 and 2.
// CONFIGS: comma-separated PRE/POST[dir], dir f (forward), s (alternating per sweep), r (per row
// and sweep); default 1/1f,2/2f,3/3f,4/4f,5/5f,2/1f,1/2f,3/2f,2/3f,2/2s,3/3s,2/2r,3/3r.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <random>
#include <sstream>
#include <string>

#include "gdp/image_io.h"
#include "gdp/solver.h"
#include "multigrid/incore_vcycle.h"
#include "multigrid/plane_ops.h"
#include "topology/topology.h"
#include "util/seconds.h"

using namespace gdp;
using namespace gdp::multigrid;
using Direction = SweepDirection;

namespace {

struct Smoother {
  int pre, post;
  Direction dir;
  std::string name;
};

std::vector<Smoother> parse_configs(const std::string& text) {
  std::vector<Smoother> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    Smoother s{0, 0, Direction::Forward, item};
    char d = 'f';
    if (std::sscanf(item.c_str(), "%d/%d%c", &s.pre, &s.post, &d) < 2 || s.pre < 0 || s.post < 0)
      throw std::runtime_error("smoother_bench: a config is PRE/POST[f|s|r], got '" + item + "'");
    s.dir = d == 's' ? Direction::AlternateSweeps : d == 'r' ? Direction::AlternateRows : Direction::Forward;
    out.push_back(s);
  }
  return out;
}

template <class T>
Plane<T> convert(const Plane<double>& p) {
  Plane<T> out(p.width, p.height);
  std::transform(p.data.begin(), p.data.end(), out.data.begin(), [](double v) { return static_cast<T>(v); });
  return out;
}

double rms_without_mean(const Plane<double>& a, const Plane<double>* ref) {
  double mean = 0.0, s = 0.0;
  const std::size_t n = a.data.size();
  for (std::size_t i = 0; i < n; ++i) mean += a.data[i] - (ref ? ref->data[i] : 0.0);
  mean /= n;
  for (std::size_t i = 0; i < n; ++i) {
    const double d = a.data[i] - (ref ? ref->data[i] : 0.0) - mean;
    s += d * d;
  }
  return std::sqrt(s / n);
}

// The manufactured solution: the photo's first channel, or waves plus offsets in Voronoi cells.
Plane<double> make_solution(int n, const char* photo_path) {
  Plane<double> u(n, n);
  if (photo_path) {
    const Image photo = read_image(photo_path).image;
    if (photo.width < n || photo.height < n) throw std::runtime_error("smoother_bench: the photo is smaller than SIZE");
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) u.row(y)[x] = photo.at(0, x, y);
    return u;
  }
  std::mt19937 rng(2010);
  std::uniform_real_distribution<double> pos(0.0, n), off(-0.15, 0.15);
  std::vector<std::array<double, 3>> seeds(12);
  for (auto& s : seeds) s = {pos(rng), pos(rng), off(rng)};
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      double best = 1e300, o = 0.0;
      for (const auto& s : seeds)
        if (const double d = std::hypot(x - s[0], y - s[1]); d < best) best = d, o = s[2];
      u.row(y)[x] = 0.5 + 0.2 * std::sin(6.0 * x / n) * std::cos(9.0 * y / n) + 0.05 * std::sin(0.3 * x) + o;
    }
  return u;
}

// Float CPU seconds of one V-cycle from zero (the minimum over `cycles` runs).
double cpu_per_cycle(const Operators<float>& ops, const Smoother& sm, const Plane<double>& b, int cycles) {
  InCoreVCycle<float> vc(ops, sm.pre, 1e-10);
  vc.set_smoother(sm.pre, sm.post, sm.dir);
  double best = 1e300;
  for (int c = 0; c < cycles; ++c) {
    Plane<float> u(b.width, b.height), bf = convert<float>(b);
    const double t0 = gdp::util::thread_cpu_seconds();
    vc.run(u, bf);
    best = std::min(best, gdp::util::thread_cpu_seconds() - t0);
  }
  return best;
}

void report(const Operators<float>& opsf, const Operators<double>& opsd, const Smoother& sm, const Plane<double>& b,
            const Plane<double>* exact, int cycles) {
  const double cpu = cpu_per_cycle(opsf, sm, b, cycles);
  InCoreVCycle<double> vc(opsd, sm.pre, 1e-10);
  vc.set_smoother(sm.pre, sm.post, sm.dir);
  Plane<double> u(b.width, b.height), bb = b;
  double last = vc.residual_norm(u, bb), product = 1.0;
  std::printf("%-6s %8.4f %7.2f ", sm.name.c_str(), cpu, b.width * double(b.height) / cpu / 1e6);
  char errors[64] = "";
  for (int c = 1; c <= cycles; ++c) {
    vc.run(u, bb);
    const double r = vc.residual_norm(u, bb);
    std::printf(" %9.3e", r / last);
    product *= r / last;
    last = r;
    if (exact && c <= 2) {
      const std::size_t used = std::strlen(errors);
      std::snprintf(errors + used, sizeof errors - used, " %.3e", rms_without_mean(u, exact));
    }
  }
  const double rho = std::pow(product, 1.0 / cycles);
  // Digits of residual per CPU second: what a cheaper cycle must not lose.
  std::printf("  mean %9.3e  digits/CPU-s %6.2f%s\n", rho, -std::log10(rho) / cpu, errors);
}

void run_problem(const char* title, const Hierarchy& h, const Plane<double>& b, const Plane<double>* exact,
                 const std::vector<Smoother>& configs, int cycles) {
  const Operators<float> opsf(h);
  const Operators<double> opsd(h);
  std::printf("\n%s: %dx%d, %d levels\n%-6s %8s %7s  residual reduction per V-cycle 1..%d, mean%s\n", title, b.width,
              b.height, static_cast<int>(h.levels.size()), "pre/po", "CPU-s", "Mpix/s", cycles,
              exact ? "; RMS error vs u* after cycles 1, 2" : "");
  for (const Smoother& sm : configs) report(opsf, opsd, sm, b, exact, cycles);
}

}  // namespace

int main(int argc, char** argv) try {
  const int n = argc > 1 ? std::atoi(argv[1]) : 2048, cycles = argc > 2 ? std::atoi(argv[2]) : 4;
  const char* photo = argc > 3 && std::string(argv[3]) != "-" ? argv[3] : nullptr;
  const auto configs =
      parse_configs(argc > 4 ? argv[4] : "1/1f,2/2f,3/3f,4/4f,5/5f,2/1f,1/2f,3/2f,2/3f,2/2s,3/3s,2/2r,3/3r");
  if (n < 8 || cycles < 1) throw std::runtime_error("smoother_bench: SIZE >= 8 and CYCLES >= 1");
  const Hierarchy h = build_hierarchy(*topology::make_topology(Domain::Planar), n, n, 0.0, 64);
  const Operators<double> ops(h);
  Plane<double> b(n, n);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  double mean = 0.0;
  for (double& v : b.data) mean += v = d(rng);
  mean /= b.data.size();
  for (double& v : b.data) v -= mean;
  run_problem("random b", h, b, nullptr, configs, cycles);
  const Plane<double> exact = make_solution(n, photo);
  Scratch<double> s;
  apply(ops.levels[0], exact, b, s);
  run_problem(photo ? "manufactured (photo)" : "manufactured (waves + offsets)", h, b, &exact, configs, cycles);
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "%s\n", e.what());
  return 2;
}
