#include "gridshell/kit/stl.h"

#include <sstream>

#include <CGAL/IO/STL.h>
#include <CGAL/Simple_cartesian.h>

#include "gridshell/core/error.h"

namespace gridshell::kit {

std::string stl_bytes(const PartMesh& part) {
  using Point = CGAL::Simple_cartesian<double>::Point_3;
  std::vector<Point> points;
  points.reserve(part.points.size());
  for (const Eigen::Vector3f& p : part.points) points.emplace_back(p.x(), p.y(), p.z());
  std::ostringstream out(std::ios::out | std::ios::binary);
  CGAL::IO::set_binary_mode(out);
  if (!CGAL::IO::write_STL(out, points, part.triangles)) {
    throw Error("STL", "CGAL's writer failed on an in-memory stream");
  }
  return std::move(out).str();
}

}  // namespace gridshell::kit
