#include "gridshell/grids/baseline_kind.h"

#include <fmt/format.h>

#include "gridshell/core/error.h"

namespace gridshell {

BaselineKind parse_baseline_kind(const std::string& word) {
  for (BaselineKind k : {BaselineKind::quad, BaselineKind::quad_aniso, BaselineKind::tri,
                         BaselineKind::voronoi_iso, BaselineKind::original})
    if (word == to_string(k)) return k;
  throw Error("--kind",
              fmt::format("'{}' is not one of quad, quad-aniso, tri, voronoi-iso, original", word));
}

const char* to_string(BaselineKind kind) {
  switch (kind) {
    case BaselineKind::quad:
      return "quad";
    case BaselineKind::quad_aniso:
      return "quad-aniso";
    case BaselineKind::tri:
      return "tri";
    case BaselineKind::voronoi_iso:
      return "voronoi-iso";
    case BaselineKind::original:
      return "original";
  }
  return "quad";
}

}  // namespace gridshell
