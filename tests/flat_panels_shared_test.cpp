// Flat panels on the six shared real surfaces (heavy; skips without ../shared/data), at the
// default field settings: every design gets flat panels — Shell and Aquadom only through the last
// resort, a few failing panels glazed as flat triangles (docs/panels.md) — with every panel flat
// to ≤ 0.5 mm, simple, no overlap the free design does not have, joints within 1 % of the span.

#include <gtest/gtest.h>

#include "gridshell/mesh/geometry.h"
#include "gridshell/mesh/overlaps.h"
#include "gridshell/mesh/topology.h"
#include "gridshell/optimize/flat_panels.h"
#include "gridshell/optimize/projector.h"
#include "gridshell/pipeline/design.h"
#include "gridshell/surfaces/load.h"
#include "test_support.h"

namespace gridshell {
namespace {

class FlatShared : public ::testing::TestWithParam<const char*> {};

TEST_P(FlatShared, EveryPanelFlatSimpleAndNearTheSurface) {
  SKIP_WITHOUT_SHARED_DATA();
  const Surface s = load_surface(test::shared_file(std::string("surfaces/") + GetParam()).string());
  DesignOptions o;
  o.analyze = analysis::AnalysisLevel::none;
  o.tessellation.cells = 300;
  o.tessellation.seed = 1;
  o.panels = PanelMode::flat;
  const DesignResult r = run_design(s, o);
  const nlohmann::json& info = r.details["flat_panels"];
  ASSERT_EQ(info["panels"], "flat") << info.dump();
  o.panels = PanelMode::free;
  const DesignResult free = run_design(s, o);
  EXPECT_LE(info["triangulated_panels"].get<int>(), free.mesh.num_faces() / 10);
  const Eigen::Vector3d extent = s.mesh.V.colwise().maxCoeff() - s.mesh.V.colwise().minCoeff();
  const double span = std::max(extent.x(), extent.y());
  const SurfaceProjector projector(s.mesh);
  const PanelShape shape = panel_shape(r.mesh, &projector);
  EXPECT_LE(shape.out_of_plane_max, 5e-4);
  EXPECT_EQ(shape.self_intersecting, 0);
  for (const auto& f : r.mesh.faces) EXPECT_TRUE(is_simple_polygon(r.mesh, f));
  EXPECT_LE(find_overlaps(r.mesh, build_topology(r.mesh)).count(),
            find_overlaps(free.mesh, build_topology(free.mesh)).count());
  EXPECT_LE(shape.surface_distance_max, 0.01 * span);
}

INSTANTIATE_TEST_SUITE_P(Surfaces, FlatShared,
                         ::testing::Values("Shell.ply", "Botanic.ply", "Neumunster.ply",
                                           "aquadom_Vouga.ply", "liliumVouga.ply",
                                           "BritishQuadTang.ply"));

}  // namespace
}  // namespace gridshell
