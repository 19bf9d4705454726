#include "gridshell/mesh/nearest.h"

#include <CGAL/Orthogonal_k_neighbor_search.h>
#include <CGAL/Search_traits_3.h>
#include <CGAL/Search_traits_adapter.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/property_map.h>
#include <boost/iterator/counting_iterator.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "gridshell/core/error.h"

namespace gridshell {

namespace {
using Kernel = CGAL::Simple_cartesian<double>;
using Point3 = Kernel::Point_3;
using PointMap = CGAL::Pointer_property_map<Point3>::type;
using Traits = CGAL::Search_traits_adapter<std::size_t, PointMap, CGAL::Search_traits_3<Kernel>>;
using Search = CGAL::Orthogonal_k_neighbor_search<Traits>;
using Tree = Search::Tree;
}  // namespace

std::vector<std::vector<int>> nearest_points(const Points& points, const Points& queries, int k) {
  if (points.rows() == 0) throw Error("nearest points", "empty point set");
  if (k < 1) throw Error("nearest points", "k must be >= 1");
  std::vector<Point3> pts;
  pts.reserve(points.rows());
  for (Eigen::Index i = 0; i < points.rows(); ++i)
    pts.emplace_back(points(i, 0), points(i, 1), points(i, 2));
  Tree tree(boost::counting_iterator<std::size_t>(0),
            boost::counting_iterator<std::size_t>(pts.size()), Tree::Splitter(),
            Traits(PointMap(pts.data())));
  tree.build();  // before the threads query it
  Search::Distance dist(PointMap(pts.data()));
  std::vector<std::vector<int>> out(queries.rows());
  // Independent queries, each filling its own entry: the same answer on any number of threads
  // (a frame response queries every vertex of the input: 1 M of them at 2 M triangles).
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, queries.rows(), 1024),
                    [&](const tbb::blocked_range<Eigen::Index>& range) {
                      for (Eigen::Index q = range.begin(); q < range.end(); ++q) {
                        Search search(tree, Point3(queries(q, 0), queries(q, 1), queries(q, 2)),
                                      static_cast<unsigned>(k), 0, true, dist);
                        out[q].reserve(k);
                        for (auto it = search.begin(); it != search.end(); ++it)
                          out[q].push_back(static_cast<int>(it->first));
                      }
                    });
  return out;
}

}  // namespace gridshell
