// The in-core schedule's memory savings change no bit: one-row mean weights, channels parked in row stores.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "bands/incore_worker.h"
#include "gdp/solver.h"
#include "multigrid/incore_vcycle.h"
#include "image_compare.h"
#include "schedule_problems.h"
#include "test_util.h"
#include "topology/topology.h"

namespace gdp {
namespace {

using multigrid::Plane;

bool same_plane_bits(const Plane<float>& a, const Plane<float>& b) {
  return a.width == b.width && a.height == b.height &&
         std::memcmp(a.data.data(), b.data.data(), a.data.size() * sizeof(float)) == 0;
}

// Feeds `rows` rows of `width` to WeightRows, row j holding value(j, i).
template <class F>
Plane<float> gathered(int width, int rows, F value) {
  multigrid::WeightRows<float> w(width, rows);
  for (int j = 0; j < rows; ++j) {
    const std::span<float> row = w.next();
    for (int i = 0; i < width; ++i) row[i] = value(j, i);
    w.add();
  }
  return w.take();
}

// A plane made a few rows at a time (InCoreWorker: while another thread fills the rows made) is
// the zeroed plane that mapped() makes, and a row made stays where it was.
TEST(InCoreMemory, PlaneRowsMadeInStepsStayWhereTheyAre) {
  const int w = 1100, h = 1000;  // (over util::kBigBuffer: huge-page memory, mapped in steps)
  Plane<float> p = Plane<float>::reserved(w, h);
  EXPECT_TRUE(p.data.empty());
  const float* first = p.row(0);
  for (int rows = 3; rows < h + 3; rows += 61) {
    p.make_rows(std::min(rows, h));
    ASSERT_EQ(p.data.size(), static_cast<std::size_t>(std::min(rows, h)) * w);
    ASSERT_EQ(p.row(0), first);
    p.at(rows % w, rows - 3) = static_cast<float>(rows);
  }
  p.make_rows(h);
  Plane<float> expected = Plane<float>::mapped(w, h);
  for (int rows = 3; rows < h + 3; rows += 61) expected.at(rows % w, rows - 3) = static_cast<float>(rows);
  EXPECT_TRUE(same_plane_bits(p, expected));
}

TEST(InCoreMemory, WeightRowsKeepOneRowUntilARowDiffers) {
  const Plane<float> same = gathered(7, 9, [](int, int i) { return i % 3 == 0 ? 0.0f : 1.0f; });
  EXPECT_EQ(same.height, 1);
  EXPECT_EQ(same.at(3, 0), 0.0f);
  EXPECT_EQ(same.at(4, 0), 1.0f);
  // -0 equals 0 but is not the same bits: the plane must become whole there.
  const Plane<float> differs = gathered(7, 9, [](int j, int i) { return j == 5 && i == 2 ? -0.0f : float(i == 2 ? 0 : 1); });
  ASSERT_EQ(differs.height, 9);
  for (int j = 0; j < 9; ++j) EXPECT_EQ(std::signbit(differs.at(2, j)), j == 5) << j;
  EXPECT_EQ(differs.at(1, 0), 1.0f);
  EXPECT_EQ(differs.at(1, 8), 1.0f);
}

// A one-row plane restricts to the same bits at every level as the whole plane of that row.
TEST(InCoreMemory, OneRowWeightsRestrictLikeTheWholePlane) {
  for (const Domain domain : {Domain::Planar, Domain::Cylindrical, Domain::Spherical}) {
    SCOPED_TRACE(test::domain_name(domain));
    const auto topo = topology::make_topology(domain);
    const int w = domain == Domain::Spherical ? 128 : 45, h = domain == Domain::Spherical ? 32 : 37;
    const multigrid::Hierarchy hier = multigrid::build_hierarchy(*topo, w, h, 0.0, 4);
    const multigrid::Operators<float> ops(hier);
    const auto value = [](int, int i) { return i % 5 == 1 ? 0.0f : 1.0f; };
    const Plane<float> one = gathered(w, h, value);
    ASSERT_EQ(one.height, 1);
    Plane<float> whole(w, h);
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i) whole.at(i, j) = value(j, i);
    const auto a = multigrid::restrict_weights(ops, 0, one), b = multigrid::restrict_weights(ops, 0, whole);
    ASSERT_EQ(a.size(), b.size());
    ASSERT_GE(a.size(), 3u);
    for (std::size_t l = 1; l < a.size(); ++l) EXPECT_TRUE(same_plane_bits(a[l], b[l])) << "level " << l;
  }
}

// 3 channels on 1, 2, 4 and 6 threads (a group per two: 2, 2, 1 and no channels parked), scratch in memory or in files,
// mean weights of one row or (a non-finite starting pixel weighs 0) the whole plane: the same bits,
// and the streamed schedule's.
TEST(InCoreMemory, ParkedChannelsAndOneRowWeightsChangeNoBit) {
  const Image img = test::random_image(61, 43, 3, 5);
  for (const bool hole : {false, true}) {
    Image start = test::with_seams(img, 0.08f, -0.06f, 0.03f);
    if (hole) start.at(1, 30, 20) = std::numeric_limits<float>::quiet_NaN();
    const auto solve_as = [&](Schedule schedule, int threads, std::size_t memory) {
      SolverOptions o;
      o.schedule = schedule;
      o.threads = threads;
      o.vcycles = 2;
      o.coarsest_size = 8;
      o.scratch_memory = memory;
      test::ExactGradients src(img, Domain::Planar, 0.0, 1.0);
      return solve(src, o, &start, nullptr);
    };
    SCOPED_TRACE(hole ? "a hole in the start" : "every pixel counted");
    const Image reference = solve_as(Schedule::InCore, 6, 1 << 30);  // (3 groups: none parked)
    for (const int threads : {1, 2, 4})  // (1 group, 2 channels parked; 2 groups, 1 parked)
      for (const std::size_t memory : {std::size_t{1} << 30, std::size_t{0}})
        EXPECT_TRUE(test::same_bits(reference, solve_as(Schedule::InCore, threads, memory)))
            << threads << " threads, memory " << memory;
    EXPECT_TRUE(test::same_bits(reference, solve_as(Schedule::Streaming, 1, 1 << 30)));
  }
}

// The norms a V-cycle measures in its own passes are residual_norm()'s bits, before and after, on
// several levels or one, with uneven sweep counts.
TEST(InCoreMemory, NormsMeasuredInTheCyclesPassesAreResidualNorms) {
  for (const Domain domain : {Domain::Planar, Domain::Spherical}) {
    for (const int coarsest : {8, 1 << 20}) {
      SCOPED_TRACE(std::string(test::domain_name(domain)) + (coarsest == 8 ? ", levels" : ", one level"));
      const auto topo = topology::make_topology(domain);
      const int w = domain == Domain::Spherical ? 128 : 53, h = domain == Domain::Spherical ? 32 : 41;
      const multigrid::Hierarchy hier = multigrid::build_hierarchy(*topo, w, h, 0.0, coarsest);
      const multigrid::Operators<float> ops(hier);
      const Image noise = test::random_image(w, h, 2, 3);
      Plane<float> u(w, h), b(w, h);
      for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) u.at(i, j) = noise.at(0, i, j), b.at(i, j) = 100.0f * (noise.at(1, i, j) - 0.5f);
      multigrid::InCoreVCycle<float> vc(ops, 2, 1e-6);
      vc.set_sweeps(2, 3);
      for (int k = 0; k < 2; ++k) {
        const double before = vc.residual_norm(u, b);
        multigrid::CycleProbe probe;
        probe.norm_before = probe.norm_after = true;
        vc.run(u, b, nullptr, &probe);
        EXPECT_EQ(probe.before, before);
        EXPECT_EQ(probe.after, vc.residual_norm(u, b));
        if (k == 0) {  // (one level: the first CG solve leaves only what it cannot reach)
          EXPECT_LT(probe.after, before);
        }
      }
    }
  }
}

// Two threads on a level's passes (PassPair: levels of kPairRows rows and more) give one thread's
// bits: u, the norms before and after and the weighted sums, with weights and uneven sweep counts,
// the norms measured or not (the lead's share of the sweeps, 0 to 2 here, depends on both).
TEST(InCoreMemory, TwoThreadsOnALevelChangeNoBit) {
  for (const Domain domain : {Domain::Planar, Domain::Cylindrical, Domain::Spherical}) {
    const int h = multigrid::InCoreVCycle<float>::kPairRows + 8, w = domain == Domain::Spherical ? 4 * h : 37;
    const auto topo = topology::make_topology(domain);
    const multigrid::Hierarchy hier = multigrid::build_hierarchy(*topo, w, h, 0.0, 8);
    const multigrid::Operators<float> ops(hier);
    const Image noise = test::random_image(w, h, 3, 7);
    Plane<float> u0(w, h), b(w, h), weights(w, h);
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i)
        u0.at(i, j) = noise.at(0, i, j), b.at(i, j) = 100.0f * (noise.at(1, i, j) - 0.5f),
        weights.at(i, j) = noise.at(2, i, j) < 0.1f ? 0.0f : 1.0f;
    const auto wl = multigrid::restrict_weights(ops, 0, weights, true);
    for (const auto& [pre, post] : {std::pair{3, 3}, std::pair{2, 3}, std::pair{1, 2}, std::pair{1, 1}})
    for (const bool norms : {true, false}) {
      SCOPED_TRACE(std::string(test::domain_name(domain)) + ", " + std::to_string(pre) + "/" + std::to_string(post) +
                   (norms ? ", norms" : ""));
      schedule::Marks marks;
      bands::PassThreads pair(marks);
      std::vector<Plane<float>> u(2, u0);
      std::vector<multigrid::CycleProbe> probe(2);
      for (int k = 0; k < 2; ++k) {
        multigrid::InCoreVCycle<float> vc(ops, pre, 1e-6);
        vc.set_sweeps(pre, post);
        if (k == 1) vc.set_pair(&pair);
        probe[k].norm_before = probe[k].norm_after = norms;
        Plane<float> bk = b;
        vc.run(u[k], bk, &wl, &probe[k]);
      }
      EXPECT_TRUE(same_plane_bits(u[0], u[1]));
      EXPECT_EQ(probe[0].before, probe[1].before);
      EXPECT_EQ(probe[0].after, probe[1].after);
      EXPECT_EQ(probe[0].dots, probe[1].dots);
      EXPECT_EQ(probe[0].level_norms, probe[1].level_norms);
      if (norms) {
        EXPECT_LT(probe[1].after, probe[1].before);
      }
    }
  }
}

// b fed row by row (RowFeed: the in-core worker's b, read from its store) gives b held whole's bits,
// on one thread and two (the lead reads rows into a ring the follower reads behind it), with b rounded
// to half floats after its first restriction (rows rounded as read from then on), over two V-cycles;
// a single level (no passes) reads its b whole.
TEST(InCoreMemory, FedRightHandSideChangesNoBit) {
  for (const Domain domain : {Domain::Planar, Domain::Spherical})
    for (const bool one_level : {false, true}) {
      const int h = one_level ? 10 : multigrid::InCoreVCycle<float>::kPairRows + 40, w = domain == Domain::Spherical ? 4 * h : 37;
      const auto topo = topology::make_topology(domain);
      const multigrid::Hierarchy hier = multigrid::build_hierarchy(*topo, w, h, 0.0, one_level ? 64 : 8);
      const multigrid::Operators<float> ops(hier);
      const Image noise = test::random_image(w, h, 2, 11);
      Plane<float> u0(w, h), b(w, h);
      for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) u0.at(i, j) = noise.at(0, i, j), b.at(i, j) = 100.0f * (noise.at(1, i, j) - 0.5f);
      multigrid::HalfPolicy half;
      half.all = true;
      for (const bool two : {false, true}) {
        SCOPED_TRACE(std::string(test::domain_name(domain)) + (one_level ? ", one level" : "") + (two ? ", two threads" : ""));
        schedule::Marks marks;
        bands::PassThreads pair(marks);
        Plane<float> whole = b, u = u0, fed_u = u0;
        multigrid::InCoreVCycle<float> a(ops, 2, 1e-6), f(ops, 2, 1e-6);
        a.set_half(&half), f.set_half(&half);
        if (two) f.set_pair(&pair);
        int next = 0, rewinds = 0;
        multigrid::RowFeed<float> feed{[&] { next = 0, ++rewinds; },
                                       [&](std::span<float> row) { std::copy_n(b.row(next++), w, row.data()); }};
        for (int k = 0; k < 2; ++k) {
          multigrid::CycleProbe pa, pf;
          pa.norm_before = pa.norm_after = pf.norm_before = pf.norm_after = true;
          a.run(u, whole, nullptr, &pa);
          f.run(fed_u, feed, nullptr, &pf);
          EXPECT_TRUE(same_plane_bits(u, fed_u)) << "cycle " << k;
          EXPECT_EQ(pa.before, pf.before);
          EXPECT_EQ(pa.after, pf.after);
        }
        ASSERT_EQ(ops.count() == 1, one_level);
        EXPECT_EQ(rewinds, one_level ? 2 : 4);  // (a descent and an ascent a cycle)
        EXPECT_EQ(feed.rounded, !one_level);
      }
    }
}

// Coarser weights held once per run of equal rows read as the whole planes' rows, and hold fewer.
TEST(InCoreMemory, WeightsHeldOnceReadAsTheWholePlanes) {
  const auto topo = topology::make_topology(Domain::Planar);
  const multigrid::Hierarchy hier = multigrid::build_hierarchy(*topo, 45, 70, 0.0, 4);
  const multigrid::Operators<float> ops(hier);
  for (const bool hole : {false, true}) {
    Plane<float> whole(45, 70);
    std::fill(whole.data.begin(), whole.data.end(), 1.0f);
    if (hole) whole.at(7, 33) = 0.0f;
    const auto a = multigrid::restrict_weights(ops, 0, whole), b = multigrid::restrict_weights(ops, 0, whole, true);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t l = 1; l < a.size(); ++l) {
      SCOPED_TRACE("level " + std::to_string(l) + (hole ? ", a hole" : ""));
      ASSERT_EQ(b[l].rows_of.size(), static_cast<std::size_t>(a[l].height));
      if (l == 1) {
        EXPECT_LT(b[l].height, a[l].height / 2);
      }
      for (int j = 0; j < a[l].height; ++j)
        EXPECT_EQ(std::memcmp(multigrid::weight_row(a[l], j), multigrid::weight_row(b[l], j), a[l].width * sizeof(float)), 0);
    }
  }
}

}  // namespace
}  // namespace gdp
