// Structured 2D generators, built from mapped patches that are merged at coincident nodes, and the
// merge of several bodies into one mesh (the 3D ones: mesh/SolidGenerators.cpp). Layer: mesh.
#include <mesh/Generators.hpp>

#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <set>

namespace mixcon {

namespace {

using Map = std::function<std::array<double, 2>(double u, double v)>;

/// One mapped block: (u, v) in [0,1]^2 -> (x, y), nu x nv elements; side names for the edges
/// v = 0, u = 1, v = 1, u = 0 (empty: interior side, not a named boundary).
struct Patch {
  Map map;
  int nu, nv;
  std::array<std::string, 4> sides;
  double gradeU = 1.0; ///< geometric growth of element size along u
};

using Point = std::array<double, 2>;

/// The point at fraction s of the straight segment from p to q (the radial lines of the mapped
/// blocks).
Point lerp(const Point &p, const Point &q, double s) {
  return {p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1])};
}

/// Parameter of grid line i out of n (geometric grading with ratio between successive sizes).
double graded(int i, int n, double ratio) {
  if (std::abs(ratio - 1.0) < 1e-14)
    return static_cast<double>(i) / n;
  return (std::pow(ratio, i) - 1.0) / (std::pow(ratio, n) - 1.0);
}

/// Builds the mesh of several patches, merging nodes that coincide within a tolerance.
Mesh buildPatches(const std::vector<Patch> &patches, ElementType type, std::string source) {
  if (type != ElementType::Quad4 && type != ElementType::Quad8)
    throw GeneratorError("mesh " + source + ": element type " + elementTypeName(type) +
                         " is not a quadrilateral (this generator is 2D; the box generator makes "
                         "hex8, hex20, tet4 and tet10 meshes)");
  Mesh mesh;
  mesh.elementType = type;
  mesh.nodesPerElement = type == ElementType::Quad8 ? 8 : 4;
  mesh.regionNames = {"body"};
  mesh.source = std::move(source);
  const bool quad8 = type == ElementType::Quad8;

  double extent = 0.0;
  for (const auto &p : patches)
    for (double u : {0.0, 1.0})
      for (double v : {0.0, 1.0}) {
        auto x = p.map(u, v);
        extent = std::max({extent, std::abs(x[0]), std::abs(x[1])});
      }
  const double tol = 1e-9 * (extent > 0 ? extent : 1.0);
  std::map<std::pair<long long, long long>, LocalIndex> lookup;
  auto addNode = [&](std::array<double, 2> x) {
    if (!std::isfinite(x[0]) || !std::isfinite(x[1]))
      throw GeneratorError(mesh.source + ": the node coordinates overflow (sizes, radii, origin or "
                                         "grading too large for the divisions)");
    const auto key = std::make_pair(std::llround(x[0] / tol), std::llround(x[1] / tol));
    // Also look at neighbouring cells so that rounding at a cell boundary cannot split a node.
    for (long long dx = -1; dx <= 1; ++dx)
      for (long long dy = -1; dy <= 1; ++dy) {
        auto it = lookup.find({key.first + dx, key.second + dy});
        if (it != lookup.end())
          return it->second;
      }
    const LocalIndex id = mesh.numNodes();
    mesh.coordinates.push_back(x[0]);
    mesh.coordinates.push_back(x[1]);
    lookup.emplace(key, id);
    return id;
  };

  for (const auto &p : patches) {
    const int mu = quad8 ? 2 * p.nu : p.nu, mv = quad8 ? 2 * p.nv : p.nv;
    // Grid of (mu+1) x (mv+1) parameter points; Quad8 uses half-steps (mid-side nodes sit at the
    // mid-parameter, so they lie exactly on curved boundaries).
    std::vector<LocalIndex> grid(static_cast<std::size_t>(mu + 1) * (mv + 1), -1);
    auto param = [&](int i, int n, double ratio) {
      if (!quad8)
        return graded(i, n, ratio);
      const int half = i / 2;
      return (i % 2 == 0) ? graded(half, n, ratio)
                          : 0.5 * (graded(half, n, ratio) + graded(half + 1, n, ratio));
    };
    for (int j = 0; j <= mv; ++j)
      for (int i = 0; i <= mu; ++i) {
        if (quad8 && i % 2 == 1 && j % 2 == 1)
          continue; // no centre node in a serendipity element
        grid[static_cast<std::size_t>(j) * (mu + 1) + i] =
            addNode(p.map(param(i, p.nu, p.gradeU), param(j, p.nv, 1.0)));
      }
    auto at = [&](int i, int j) { return grid[static_cast<std::size_t>(j) * (mu + 1) + i]; };
    for (int j = 0; j < p.nv; ++j)
      for (int i = 0; i < p.nu; ++i) {
        const LocalIndex e = mesh.numElements();
        if (quad8) {
          const int I = 2 * i, J = 2 * j;
          for (LocalIndex n : {at(I, J), at(I + 2, J), at(I + 2, J + 2), at(I, J + 2), at(I + 1, J),
                               at(I + 2, J + 1), at(I + 1, J + 2), at(I, J + 1)})
            mesh.connectivity.push_back(n);
        } else {
          for (LocalIndex n : {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)})
            mesh.connectivity.push_back(n);
        }
        mesh.elementRegion.push_back(0);
        if (j == 0 && !p.sides[0].empty())
          mesh.boundaries[p.sides[0]].push_back({e, 0});
        if (i == p.nu - 1 && !p.sides[1].empty())
          mesh.boundaries[p.sides[1]].push_back({e, 1});
        if (j == p.nv - 1 && !p.sides[2].empty())
          mesh.boundaries[p.sides[2]].push_back({e, 2});
        if (i == 0 && !p.sides[3].empty())
          mesh.boundaries[p.sides[3]].push_back({e, 3});
      }
  }
  mesh.finalizeIds();
  return mesh;
}

/// Index of the node closest to (x, y).
LocalIndex closestNode(const Mesh &mesh, double x, double y) {
  LocalIndex best = 0;
  double bestD = 1e300;
  for (LocalIndex n = 0; n < mesh.numNodes(); ++n) {
    const double d = std::hypot(mesh.x(n) - x, mesh.y(n) - y);
    if (d < bestD) {
      bestD = d;
      best = n;
    }
  }
  return best;
}

} // namespace

void detail::requirePositive(const char *what, double v, const std::string &gen) {
  if (!(v > 0.0))
    throw GeneratorError("mesh generator " + gen + ": " + what + " must be positive");
}

Mesh rectangleMesh(double lx, double ly, int nx, int ny, ElementType type, double x0, double y0,
                   double gx, double gy) {
  detail::requirePositive("size[0]", lx, "rectangle");
  detail::requirePositive("size[1]", ly, "rectangle");
  detail::requirePositive("divisions[0]", nx, "rectangle");
  detail::requirePositive("divisions[1]", ny, "rectangle");
  detail::requirePositive("grading[0]", gx, "rectangle");
  detail::requirePositive("grading[1]", gy, "rectangle");
  // Power grading at the grid lines, linear in between: straight-sided elements keep their
  // Quad8 mid-side nodes at the edge midpoints (a power map would move them toward the quarter
  // point, where the Jacobian vanishes).
  const auto grade = [](double u, int n, double g) {
    const double s = u * n;
    const int i = std::min(static_cast<int>(s), n - 1);
    const double a = std::pow(static_cast<double>(i) / n, g);
    const double b = std::pow(static_cast<double>(i + 1) / n, g);
    return a + (s - i) * (b - a);
  };
  Patch p{[=](double u, double v) {
            return std::array<double, 2>{x0 + grade(u, nx, gx) * lx, y0 + grade(v, ny, gy) * ly};
          },
          nx,
          ny,
          {"bottom", "right", "top", "left"}};
  Mesh mesh = buildPatches({p}, type, "generator rectangle");
  mesh.nodeSets["bottom_left"] = {closestNode(mesh, x0, y0)};
  mesh.nodeSets["bottom_right"] = {closestNode(mesh, x0 + lx, y0)};
  mesh.nodeSets["top_left"] = {closestNode(mesh, x0, y0 + ly)};
  mesh.nodeSets["top_right"] = {closestNode(mesh, x0 + lx, y0 + ly)};
  mesh.nodeSets["left_center"] = {closestNode(mesh, x0, y0 + 0.5 * ly)};
  mesh.nodeSets["right_center"] = {closestNode(mesh, x0 + lx, y0 + 0.5 * ly)};
  return mesh;
}

Mesh quarterAnnulusMesh(double a, double b, int nr, int nt, ElementType type, double ratio) {
  detail::requirePositive("inner_radius", a, "quarter_annulus");
  detail::requirePositive("divisions[0]", nr, "quarter_annulus");
  detail::requirePositive("divisions[1]", nt, "quarter_annulus");
  detail::requirePositive("grading", ratio, "quarter_annulus");
  if (!(b > a))
    throw GeneratorError("mesh generator quarter_annulus: outer_radius must exceed inner_radius");
  Patch p{[=](double u, double v) {
            const double r = a + u * (b - a), t = v * M_PI / 2;
            return std::array<double, 2>{r * std::cos(t), r * std::sin(t)};
          },
          nr,
          nt,
          {"bottom", "outer", "left", "inner"},
          ratio};
  return buildPatches({p}, type, "generator quarter_annulus");
}

Mesh plateWithHoleMesh(double a, double w, double h, int nr, int nt, ElementType type,
                       double ratio) {
  detail::requirePositive("hole_radius", a, "plate_with_hole");
  detail::requirePositive("divisions[0]", nr, "plate_with_hole");
  detail::requirePositive("divisions[1]", nt, "plate_with_hole");
  detail::requirePositive("grading", ratio, "plate_with_hole");
  if (!(w > a && h > a))
    throw GeneratorError(
        "mesh generator plate_with_hole: width and height must exceed hole_radius");
  const double tc = std::atan2(h, w); // angle of the plate corner
  // Block 1: theta in [0, tc], outer side on x = w. Block 2: theta in [tc, pi/2], outer on y = h.
  Patch right{[=](double u, double v) {
                const double t = v * tc;
                return lerp({a * std::cos(t), a * std::sin(t)}, {w, w * std::tan(t)}, u);
              },
              nr,
              nt,
              {"bottom", "right", "", "hole"},
              ratio};
  Patch top{
      [=](double u, double v) {
        const double t = tc + v * (M_PI / 2 - tc);
        return lerp({a * std::cos(t), a * std::sin(t)}, {h * std::cos(t) / std::sin(t), h}, u);
      },
      nr,
      nt,
      {"", "top", "left", "hole"},
      ratio};
  return buildPatches({right, top}, type, "generator plate_with_hole");
}

Mesh quarterDiskMesh(double r, int n, int m, ElementType type, double angularGrading,
                     double radialGrading) {
  detail::requirePositive("radius", r, "quarter_disk");
  detail::requirePositive("divisions[0]", n, "quarter_disk");
  detail::requirePositive("divisions[1]", m, "quarter_disk");
  detail::requirePositive("grading[0]", angularGrading, "quarter_disk");
  detail::requirePositive("grading[1]", radialGrading, "quarter_disk");
  const double c = 0.5 * r; // core square side
  // Grading: g clusters the core's x and the upper block's arc parameter toward x = 0 (the arc
  // point (0, r)); h clusters both curved blocks' radial parameter toward the arc. Shared edges
  // use the same functions, so the blocks stay conforming.
  const double p = angularGrading, q = radialGrading;
  const auto g = [p](double u) { return std::pow(u, p); };
  const auto h = [q](double s) { return 1.0 - std::pow(1.0 - s, q); };
  Patch core{[=](double u, double v) {
               return std::array<double, 2>{g(u) * c, v * c};
             },
             n,
             n,
             {"bottom", "", "", "left"}};
  // Lower block: u from the core edge x = c (u = 0) to the arc (u = 1), v along it.
  Patch lower{[=](double u, double v) {
                const double t = v * M_PI / 4;
                return lerp({c, v * c}, {r * std::cos(t), r * std::sin(t)}, h(u));
              },
              m,
              n,
              {"bottom", "arc", "", ""}};
  // Upper block: u along the core's top edge from x = 0 to the diagonal, v from the core
  // (v = 0) to the arc, so that (u, v) is counter-clockwise.
  Patch upper{[=](double u, double v) {
                const double t = M_PI / 2 - g(u) * M_PI / 4;
                return lerp({g(u) * c, c}, {r * std::cos(t), r * std::sin(t)}, h(v));
              },
              n,
              m,
              {"", "", "arc", "left"}};
  Mesh mesh = buildPatches({core, lower, upper}, type, "generator quarter_disk");
  mesh.nodeSets["center"] = {closestNode(mesh, 0.0, 0.0)};
  mesh.nodeSets["arc_bottom"] = {closestNode(mesh, r, 0.0)};
  mesh.nodeSets["arc_left"] = {closestNode(mesh, 0.0, r)};
  return mesh;
}

Mesh halfDiskMesh(double r, int n, int m, ElementType type, double angularGrading,
                  double radialGrading) {
  detail::requirePositive("radius", r, "half_disk");
  detail::requirePositive("divisions[0]", n, "half_disk");
  detail::requirePositive("divisions[1]", m, "half_disk");
  detail::requirePositive("grading[0]", angularGrading, "half_disk");
  detail::requirePositive("grading[1]", radialGrading, "half_disk");
  const double c = 0.5 * r; // core: [-c, c] x [0, c]
  // Grading: g clusters the core's x and the top block's arc parameter toward the middle (the
  // arc point (0, r)), symmetrically; h clusters the curved blocks' radial parameter toward the
  // arc. Shared edges use the same functions, so the blocks stay conforming.
  const double p = angularGrading, q = radialGrading;
  const auto g = [p](double u) {
    const double s = 2.0 * u - 1.0;
    return 0.5 + 0.5 * (s < 0.0 ? -std::pow(-s, p) : std::pow(s, p));
  };
  const auto h = [q](double s) { return 1.0 - std::pow(1.0 - s, q); };
  Patch core{[=](double u, double v) {
               return std::array<double, 2>{(2 * g(u) - 1) * c, v * c};
             },
             2 * n,
             n,
             {"bottom", "", "", ""}};
  // Right block: u from the core edge x = c to the arc, v counter-clockwise from 0 to 45 deg.
  Patch right{[=](double u, double v) {
                const double t = v * M_PI / 4;
                return lerp({c, v * c}, {r * std::cos(t), r * std::sin(t)}, h(u));
              },
              m,
              n,
              {"bottom", "arc", "", ""}};
  // Top block: u along the core's top edge (x from -c to c) and the arc from 135 down to 45
  // deg, v from the core to the arc (counter-clockwise (u, v)).
  Patch top{[=](double u, double v) {
              const double t = 3 * M_PI / 4 - g(u) * M_PI / 2;
              return lerp({(2 * g(u) - 1) * c, c}, {r * std::cos(t), r * std::sin(t)}, h(v));
            },
            2 * n,
            m,
            {"", "", "arc", ""}};
  // Left block: u from the core edge x = -c to the arc, v counter-clockwise from 135 to 180 deg.
  Patch left{[=](double u, double v) {
               const double t = 3 * M_PI / 4 + v * M_PI / 4;
               return lerp({-c, (1 - v) * c}, {r * std::cos(t), r * std::sin(t)}, h(u));
             },
             m,
             n,
             {"", "arc", "bottom", ""}};
  Mesh mesh = buildPatches({core, right, top, left}, type, "generator half_disk");
  mesh.nodeSets["center"] = {closestNode(mesh, 0.0, 0.0)};
  mesh.nodeSets["arc_right"] = {closestNode(mesh, r, 0.0)};
  mesh.nodeSets["arc_left"] = {closestNode(mesh, -r, 0.0)};
  return mesh;
}

Mesh pinnedPlateMesh(double r, double b, double e, double l, int n, int m, int nEnd, int nFar,
                     ElementType type, double ratio) {
  const std::string gen = "pinned_plate";
  detail::requirePositive("hole_radius", r, gen);
  detail::requirePositive("divisions[0]", n, gen);
  detail::requirePositive("divisions[1]", m, gen);
  detail::requirePositive("divisions[2]", nEnd, gen);
  detail::requirePositive("divisions[3]", nFar, gen);
  detail::requirePositive("grading", ratio, gen);
  const double a = b / std::sqrt(3.0); // O-grid half-length: its corners lie at 60 and 120 deg
  if (!(a > 1.05 * r))
    throw GeneratorError("mesh generator pinned_plate: half_width must exceed sqrt(3) * 1.05 * "
                         "hole_radius (the O-grid around the hole needs room)");
  if (!(e > a * 1.05) || !(l > a * 1.05))
    throw GeneratorError("mesh generator pinned_plate: end_distance and length must exceed "
                         "half_width / sqrt(3) by 5 % (the O-grid around the hole)");
  const double third = M_PI / 3;
  const auto hole = [r](double t) { return Point{r * std::cos(t), r * std::sin(t)}; };
  // Sectors: u radial from the hole (graded), v counter-clockwise along it.
  Patch right{[=](double u, double v) {
                const double t = v * third;
                return lerp(hole(t), {a, a * std::tan(t)}, u);
              },
              m,
              n,
              {"bottom", "", "", "hole"},
              ratio};
  Patch top{[=](double u, double v) {
              const double t = third + v * third;
              return lerp(hole(t), {b * std::cos(t) / std::sin(t), b}, u);
            },
            m,
            n,
            {"", "top", "", "hole"},
            ratio};
  Patch left{[=](double u, double v) {
               const double t = 2 * third + v * third;
               return lerp(hole(t), {-a, a * std::tan((1.0 - v) * third)}, u);
             },
             m,
             n,
             {"", "", "bottom", "hole"},
             ratio};
  // Blocks: rows at the sectors' outer node heights y = a tan(v pi / 3).
  Patch end{[=](double u, double v) {
              return Point{-e + u * (e - a), a * std::tan(v * third)};
            },
            nEnd,
            n,
            {"bottom", "", "top", "end"},
            1.0 / ratio};
  Patch far{[=](double u, double v) {
              return Point{a + u * (l - a), a * std::tan(v * third)};
            },
            nFar,
            n,
            {"bottom", "far", "top", ""},
            ratio};
  Mesh mesh = buildPatches({right, top, left, end, far}, type, "generator " + gen);
  mesh.nodeSets["hole_bearing"] = {closestNode(mesh, -r, 0.0)};
  mesh.nodeSets["hole_top"] = {closestNode(mesh, 0.0, r)};
  mesh.nodeSets["far_bottom"] = {closestNode(mesh, l, 0.0)};
  return mesh;
}

} // namespace mixcon

namespace mixcon {

Mesh mergeMeshes(const std::vector<MeshBody> &bodies) {
  if (bodies.empty())
    throw InputError("mesh bodies: the list is empty");
  Mesh out;
  out.elementType = bodies.front().mesh.elementType;
  out.nodesPerElement = bodies.front().mesh.nodesPerElement;
  std::set<std::string> names;
  std::string source;
  for (const MeshBody &b : bodies) {
    const Mesh &m = b.mesh;
    if (m.dim() != 2)
      throw InputError("mesh bodies: body '" + b.name + "' is a " + std::to_string(m.dim()) +
                       "D mesh (" + elementTypeName(m.elementType) +
                       "); several bodies in one mesh are 2D only so far (issue 17)");
    if (!names.insert(b.name).second)
      throw InputError("mesh bodies: the name '" + b.name + "' is used twice");
    if (m.elementType != out.elementType)
      throw InputError("mesh bodies: body '" + b.name +
                       "' has another element type than the first body");
    const LocalIndex nodeBase = out.numNodes(), elementBase = out.numElements();
    for (LocalIndex p = 0; p < m.numNodes(); ++p) {
      out.coordinates.push_back(m.x(p) + b.offset[0]);
      out.coordinates.push_back(m.y(p) + b.offset[1]);
    }
    for (LocalIndex n : m.connectivity)
      out.connectivity.push_back(n + nodeBase);
    const int regionBase = static_cast<int>(out.regionNames.size());
    for (const auto &r : m.regionNames)
      out.regionNames.push_back(m.regionNames.size() == 1 ? b.name : b.name + "." + r);
    for (int r : m.elementRegion)
      out.elementRegion.push_back(r + regionBase);
    for (const auto &[name, edges] : m.boundaries) {
      auto &e = out.boundaries[b.name + "." + name];
      for (const BoundaryEdge &x : edges)
        e.push_back({x.element + elementBase, x.edge});
    }
    for (const auto &[name, nodes] : m.nodeSets) {
      auto &e = out.nodeSets[b.name + "." + name];
      for (LocalIndex n : nodes)
        e.push_back(n + nodeBase);
    }
    source += (source.empty() ? "" : ", ") + b.name + ": " + m.source;
  }
  out.source = "bodies (" + source + ")";
  out.finalizeIds();
  return out;
}

} // namespace mixcon
