// Structured 3D generators: the Hex8, Hex20, Tet4 and Tet10 box as a tensor grid, a 2D mesh
// extruded, and a thick spherical shell sector of box patches (the 2D ones:
// mesh/Generators.cpp). Layer: mesh.
#include <mesh/Generators.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <map>

namespace mixcon {

namespace {

/// Index of the node of `candidates` closest to p (the first one of equal distances).
LocalIndex closestNode3(const Mesh &mesh, const std::vector<LocalIndex> &candidates,
                        const std::array<double, 3> &p) {
  LocalIndex best = candidates.front();
  double bestD = std::numeric_limits<double>::infinity();
  for (LocalIndex n : candidates) {
    const double dx = mesh.x(n) - p[0], dy = mesh.y(n) - p[1], dz = mesh.z(n) - p[2];
    const double d = dx * dx + dy * dy + dz * dz;
    if (d < bestD) {
      bestD = d;
      best = n;
    }
  }
  return best;
}

} // namespace

Mesh boxMesh(double lx, double ly, double lz, int nx, int ny, int nz, ElementType type, double x0,
             double y0, double z0, double gx, double gy, double gz) {
  const std::string gen = "box";
  detail::requirePositive("size[0]", lx, gen);
  detail::requirePositive("size[1]", ly, gen);
  detail::requirePositive("size[2]", lz, gen);
  detail::requirePositive("divisions[0]", nx, gen);
  detail::requirePositive("divisions[1]", ny, gen);
  detail::requirePositive("divisions[2]", nz, gen);
  detail::requirePositive("grading[0]", gx, gen);
  detail::requirePositive("grading[1]", gy, gen);
  detail::requirePositive("grading[2]", gz, gen);
  if (type != ElementType::Hex8 && type != ElementType::Hex20 && type != ElementType::Tet4 &&
      type != ElementType::Tet10)
    throw GeneratorError("mesh generator box: element type " + elementTypeName(type) +
                         " is not a 3D solid (the box makes hex8, hex20, tet4 and tet10 meshes)");
  const bool serendipity = type == ElementType::Hex20;
  const bool tet = type == ElementType::Tet4 || type == ElementType::Tet10;
  const bool quadratic = serendipity || type == ElementType::Tet10;
  const int npe = dispatchElement(type, [](auto t) { return decltype(t)::kNumNodes; });
  const int perCell = tet ? 6 : 1; // a cell is split into 6 tetrahedra
  // Nodes live on a lattice of (mx + 1) x (my + 1) x (mz + 1) points: the grid itself for Hex8
  // and Tet4, the grid with its half steps for Hex20 and Tet10 (point (I, J, K), even indices on
  // grid lines; Tet10 uses every point: edge, face-diagonal and cell-diagonal midpoints).
  const int step = quadratic ? 2 : 1;
  const long mx = static_cast<long>(step) * nx, my = static_cast<long>(step) * ny,
             mz = static_cast<long>(step) * nz;
  // Node and connectivity indices are LocalIndex: refuse before anything is allocated.
  const double most = static_cast<double>(std::numeric_limits<LocalIndex>::max());
  const double corners = (nx + 1.0) * (ny + 1.0) * (nz + 1.0);
  const double midEdges = quadratic ? nx * (ny + 1.0) * (nz + 1.0) + (nx + 1.0) * ny * (nz + 1.0) +
                                          (nx + 1.0) * (ny + 1.0) * nz
                                    : 0.0;
  const double lattice = (mx + 1.0) * (my + 1.0) * (mz + 1.0);
  if (corners + midEdges > most || lattice > most || double(npe) * perCell * nx * ny * nz > most)
    throw GeneratorError("mesh generator box: divisions too large (node or connectivity indices "
                         "beyond " +
                         std::to_string(std::numeric_limits<LocalIndex>::max()) + ")");

  // Grid line coordinates along each axis: x0 + l (i / n)^g; with half steps for Hex20, the
  // mid-edge nodes at the middle of each (graded, straight) element edge.
  const auto lines = [&](double origin, double length, int n, double g, const char *axis) {
    std::vector<double> v(static_cast<std::size_t>(n) + 1);
    for (int i = 0; i <= n; ++i) {
      v[i] = origin + length * std::pow(static_cast<double>(i) / n, g);
      if (!std::isfinite(v[i]))
        throw GeneratorError(std::string("mesh generator box: the ") + axis +
                             " coordinates overflow (size, origin or grading too large)");
    }
    v[n] = origin + length; // the far face exactly where it was asked for
    if (!quadratic)
      return v;
    std::vector<double> half(2 * static_cast<std::size_t>(n) + 1);
    for (int i = 0; i <= 2 * n; ++i)
      half[i] = i % 2 == 0 ? v[i / 2] : 0.5 * (v[i / 2] + v[i / 2 + 1]);
    return half;
  };
  const std::vector<double> xs = lines(x0, lx, nx, gx, "x"), ys = lines(y0, ly, ny, gy, "y"),
                            zs = lines(z0, lz, nz, gz, "z");

  Mesh mesh;
  mesh.elementType = type;
  mesh.nodesPerElement = npe;
  mesh.regionNames = {"body"};
  mesh.source = "generator box";
  // Node numbers: the lattice points in lexicographic order (I fastest, then J, then K), skipping
  // those with two or three odd indices (face and cell centres, which a serendipity element does
  // not have). For Hex8 every lattice point is a node: x fastest, then y, then z.
  const auto latticeIndex = [&](long I, long J, long K) {
    return static_cast<std::size_t>(I + (mx + 1) * (J + (my + 1) * K));
  };
  std::vector<LocalIndex> number(static_cast<std::size_t>(lattice), -1);
  mesh.coordinates.reserve(3 * static_cast<std::size_t>(corners + midEdges));
  LocalIndex count = 0;
  for (long K = 0; K <= mz; ++K)
    for (long J = 0; J <= my; ++J)
      for (long I = 0; I <= mx; ++I) {
        if (serendipity && (I % 2) + (J % 2) + (K % 2) > 1)
          continue; // a face or cell centre of the half-step lattice
        number[latticeIndex(I, J, K)] = count++;
        mesh.coordinates.push_back(xs[I]);
        mesh.coordinates.push_back(ys[J]);
        mesh.coordinates.push_back(zs[K]);
      }
  const auto node = [&](long I, long J, long K) { return number[latticeIndex(I, J, K)]; };

  if (tet) {
    // Six tetrahedra per cell around its main diagonal, corner 0 (0, 0, 0) to corner 6 (1, 1, 1)
    // (Hex8 numbering): tetrahedron p walks from corner 0 to corner 6 along the cell edges in the
    // axis order of permutation p (Kuhn's split). Every cell face is cut along the diagonal from
    // its corner nearest (0, 0, 0) to its corner nearest (1, 1, 1), the same for the two cells
    // that share it: the mesh is conforming. The walk's volume has the sign of p; odd
    // permutations swap their second and third corners, so that every Jacobian is positive
    // (grading scales the axes by positive factors and keeps the sign).
    constexpr int perms[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {2, 1, 0}, {1, 0, 2}};
    const std::size_t elements = static_cast<std::size_t>(perCell) * nx * ny * nz;
    mesh.connectivity.reserve(static_cast<std::size_t>(npe) * elements);
    mesh.elementRegion.assign(elements, 0);
    // A face lies on the box's face of axis d when its three corners have cell offset 0 (min) or
    // 1 (max) along d in a cell at that end of the grid.
    const char *names[3][2] = {{"xmin", "xmax"}, {"ymin", "ymax"}, {"zmin", "zmax"}};
    for (const auto &row : names)
      for (const char *name : row)
        mesh.boundaries[name];
    const int cells[3] = {nx, ny, nz};
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
          for (int p = 0; p < 6; ++p) {
            const LocalIndex e = mesh.numElements();
            // Corner offsets (0 or 1 per axis) of the walk.
            int c[4][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {1, 1, 1}};
            c[1][perms[p][0]] = 1;
            c[2][perms[p][0]] = c[2][perms[p][1]] = 1;
            if (p >= 3) // odd permutation
              for (int d = 0; d < 3; ++d)
                std::swap(c[1][d], c[2][d]);
            const long base[3] = {static_cast<long>(step) * i, static_cast<long>(step) * j,
                                  static_cast<long>(step) * k};
            // Lattice point between corners a and b (a == b: the corner itself).
            const auto between = [&](int a, int b) {
              return node(base[0] + (c[a][0] + c[b][0]) * step / 2,
                          base[1] + (c[a][1] + c[b][1]) * step / 2,
                          base[2] + (c[a][2] + c[b][2]) * step / 2);
            };
            for (int a = 0; a < 4; ++a)
              mesh.connectivity.push_back(between(a, a));
            if (quadratic)
              for (int m = 0; m < 6; ++m)
                mesh.connectivity.push_back(
                    between(Tet10::edgeCorner(m, 0), Tet10::edgeCorner(m, 1)));
            const int cell[3] = {i, j, k};
            for (int f = 0; f < Tet4::kNumSides; ++f)
              for (int d = 0; d < 3; ++d)
                for (int end = 0; end < 2; ++end) {
                  if (cell[d] != (end == 0 ? 0 : cells[d] - 1))
                    continue;
                  bool on = true;
                  for (int q = 0; q < 3; ++q)
                    on = on && c[Tet4::sideNode(f, q)][d] == end;
                  if (on)
                    mesh.boundaries[names[d][end]].push_back({e, f});
                }
          }
  } else {
    // Local node a of an element sits at lattice offset step (xi_a + 1) / 2 from its first corner
    // (natural coordinates of the element's own node order: Hex8 or Hex20, core/ElementTraits.hpp).
    std::vector<std::array<int, 3>> offset(npe);
    for (int a = 0; a < npe; ++a) {
      double xi[3];
      if (serendipity)
        Hex20::nodeNatural(a, xi);
      else
        Hex8::nodeNatural(a, xi);
      for (int d = 0; d < 3; ++d)
        offset[a][d] = static_cast<int>(std::lround(xi[d] + 1.0)) * step / 2;
    }
    const std::size_t elements = static_cast<std::size_t>(nx) * ny * nz;
    mesh.connectivity.reserve(static_cast<std::size_t>(npe) * elements);
    mesh.elementRegion.assign(elements, 0);
    // Faces in Hex8::sideNode numbering (Hex20's faces have the same numbers): 0 z-, 1 z+, 2 y-,
    // 3 x+, 4 y+, 5 x-.
    auto &zmin = mesh.boundaries["zmin"], &zmax = mesh.boundaries["zmax"];
    auto &ymin = mesh.boundaries["ymin"], &ymax = mesh.boundaries["ymax"];
    auto &xmin = mesh.boundaries["xmin"], &xmax = mesh.boundaries["xmax"];
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
          const LocalIndex e = mesh.numElements();
          for (int a = 0; a < npe; ++a)
            mesh.connectivity.push_back(node(static_cast<long>(step) * i + offset[a][0],
                                             static_cast<long>(step) * j + offset[a][1],
                                             static_cast<long>(step) * k + offset[a][2]));
          if (k == 0)
            zmin.push_back({e, 0});
          if (k == nz - 1)
            zmax.push_back({e, 1});
          if (j == 0)
            ymin.push_back({e, 2});
          if (i == nx - 1)
            xmax.push_back({e, 3});
          if (j == ny - 1)
            ymax.push_back({e, 4});
          if (i == 0)
            xmin.push_back({e, 5});
        }
  }
  for (int cz = 0; cz < 2; ++cz)
    for (int cy = 0; cy < 2; ++cy)
      for (int cx = 0; cx < 2; ++cx)
        mesh.nodeSets["corner_" + std::to_string(cx) + std::to_string(cy) + std::to_string(cz)] = {
            node(cx * mx, cy * my, cz * mz)};
  // Face centres: the node of the face closest to its centre, corner or mid-edge node.
  for (int side = 0; side < 2; ++side) {
    std::vector<LocalIndex> face;
    for (long K = 0; K <= mz; ++K)
      for (long J = 0; J <= my; ++J)
        if (const LocalIndex n = node(side * mx, J, K); n >= 0)
          face.push_back(n);
    mesh.nodeSets[side == 0 ? "xmin_center" : "xmax_center"] = {
        closestNode3(mesh, face, {side == 0 ? x0 : x0 + lx, y0 + 0.5 * ly, z0 + 0.5 * lz})};
  }
  mesh.finalizeIds();
  return mesh;
}

Mesh extrudeMesh(const Mesh &plane, double length, int layers, double grading) {
  const std::string gen = "extrude";
  detail::requirePositive("length", length, gen);
  detail::requirePositive("divisions", layers, gen);
  detail::requirePositive("grading", grading, gen);
  if (plane.dim() != 2)
    throw GeneratorError("mesh generator extrude: the section must be a 2D (quad4 or quad8) mesh");
  const bool quadratic = plane.elementType == ElementType::Quad8;
  const LocalIndex nn = plane.numNodes(), ne = plane.numElements();
  Mesh out;
  out.elementType = quadratic ? ElementType::Hex20 : ElementType::Hex8;
  out.nodesPerElement = quadratic ? 20 : 8;
  // Corner nodes of the section (Hex20: they get the vertical mid-edge nodes), numbered compactly.
  std::vector<LocalIndex> corner(nn, -1);
  LocalIndex corners = 0;
  for (LocalIndex e = 0; e < ne; ++e)
    for (int a = 0; a < 4; ++a)
      if (corner[plane.node(e, a)] < 0)
        corner[plane.node(e, a)] = corners++;
  const double most = static_cast<double>(std::numeric_limits<LocalIndex>::max());
  if ((layers + 1.0) * nn + (quadratic ? 1.0 * layers * corners : 0.0) > most ||
      1.0 * layers * ne * out.nodesPerElement > most)
    throw GeneratorError("mesh generator extrude: " + std::to_string(layers) +
                         " layers make more nodes than a LocalIndex holds");
  const auto level = [&](double k) { return length * std::pow(k / layers, grading); };
  const auto gridNode = [&](int k, LocalIndex n) { return static_cast<LocalIndex>(k * nn + n); };
  const auto halfNode = [&](int k, LocalIndex n) {
    return static_cast<LocalIndex>((layers + 1) * nn + k * corners + corner[n]);
  };
  for (int k = 0; k <= layers; ++k)
    for (LocalIndex n = 0; n < nn; ++n)
      out.coordinates.insert(out.coordinates.end(), {plane.x(n), plane.y(n), level(k)});
  if (quadratic) {
    std::vector<LocalIndex> byIndex(corners);
    for (LocalIndex n = 0; n < nn; ++n)
      if (corner[n] >= 0)
        byIndex[corner[n]] = n;
    for (int k = 0; k < layers; ++k)
      for (LocalIndex n : byIndex) // z half way between the grid lines: straight vertical edges
        out.coordinates.insert(out.coordinates.end(),
                               {plane.x(n), plane.y(n), 0.5 * (level(k) + level(k + 1))});
  }
  for (int k = 0; k < layers; ++k)
    for (LocalIndex e = 0; e < ne; ++e) {
      // VTK / core/ElementTraits.hpp order: the section's corners at z_k (counter-clockwise seen
      // from +z), then at z_k+1; Hex20: the mid-edge nodes of those two faces (the section's
      // mid-side nodes), then the vertical ones.
      for (int top = 0; top < 2; ++top)
        for (int a = 0; a < 4; ++a)
          out.connectivity.push_back(gridNode(k + top, plane.node(e, a)));
      if (quadratic) {
        for (int top = 0; top < 2; ++top)
          for (int a = 4; a < 8; ++a)
            out.connectivity.push_back(gridNode(k + top, plane.node(e, a)));
        for (int a = 0; a < 4; ++a)
          out.connectivity.push_back(halfNode(k, plane.node(e, a)));
      }
      out.elementRegion.push_back(plane.elementRegion[e]);
    }
  out.regionNames = plane.regionNames;
  // Quad edge j (corners j, j + 1) sweeps the hexahedron's face 2 + j (core/ElementTraits.hpp).
  for (const auto &[name, edges] : plane.boundaries)
    for (int k = 0; k < layers; ++k)
      for (const BoundaryEdge &b : edges)
        out.boundaries[name].push_back({static_cast<LocalIndex>(k * ne) + b.element, 2 + b.edge});
  for (LocalIndex e = 0; e < ne; ++e) {
    out.boundaries["zmin"].push_back({e, 0});
    out.boundaries["zmax"].push_back({static_cast<LocalIndex>((layers - 1) * ne) + e, 1});
  }
  for (const auto &[name, nodes] : plane.nodeSets) {
    auto &line = out.nodeSets[name];
    for (LocalIndex n : nodes) {
      for (int k = 0; k <= layers; ++k)
        line.push_back(gridNode(k, n));
      if (quadratic && corner[n] >= 0)
        for (int k = 0; k < layers; ++k)
          line.push_back(halfNode(k, n));
    }
  }
  out.source = plane.source + " extruded";
  out.finalizeIds();
  return out;
}

Mesh sphereShellMesh(double a, double b, int n, int m, ElementType type, double grading) {
  const std::string gen = "sphere_shell";
  detail::requirePositive("inner_radius", a, gen);
  detail::requirePositive("divisions[0]", n, gen);
  detail::requirePositive("divisions[1]", m, gen);
  detail::requirePositive("grading", grading, gen);
  if (!(b > a))
    throw GeneratorError("mesh generator sphere_shell: outer_radius must exceed inner_radius");
  if (spatialDimension(type) != 3)
    throw GeneratorError("mesh generator sphere_shell: element type " + elementTypeName(type) +
                         " is not a 3D solid (hex8, hex20, tet4 or tet10)");
  // Node and connectivity indices are LocalIndex: refuse before anything is allocated (three
  // boxes, the largest count before merging; boxMesh checks one).
  const bool tet = type == ElementType::Tet4 || type == ElementType::Tet10;
  const double cells = 3.0 * n * n * m, most = std::numeric_limits<LocalIndex>::max();
  if (cells * (tet ? 6 : 1) * dispatchElement(type, [](auto t) { return decltype(t)::kNumNodes; }) >
      most)
    throw GeneratorError("mesh generator sphere_shell: divisions [" + std::to_string(n) + ", " +
                         std::to_string(m) + "] make more nodes than a LocalIndex holds");
  // Patch p maps the unit box (u, v, w) to r(w) c / |c| with the cube point c: patch 0 on x = 1,
  // c = (1, t(u), t(v)); patch 1 on y = 1, c = (t(v), 1, t(u)); patch 2 on z = 1,
  // c = (t(u), t(v), 1); t(s) = tan(pi s / 4). Each keeps the box's orientation (u, v, w map to a
  // right-handed frame), and neighbouring patches meet on the planes x = y, y = z, z = x with the
  // same parameters (so the same nodes, and for tetrahedra the same face diagonals).
  // Box faces: xmin u = 0, ymin v = 0, zmin w = 0 (inner), zmax w = 1 (outer); xmax and ymax are
  // the interfaces. Patch p's u = 0 and v = 0 lie on these symmetry planes:
  const char *onU0[3] = {"ymin", "zmin", "xmin"}, *onV0[3] = {"zmin", "xmin", "ymin"};
  Mesh out;
  out.elementType = type;
  std::map<std::array<long long, 3>, LocalIndex> merged; // rounded coordinates -> node
  const double quantum = 1e-9 * b;
  for (int patch = 0; patch < 3; ++patch) {
    const Mesh box = boxMesh(1.0, 1.0, 1.0, n, n, m, type, 0.0, 0.0, 0.0, 1.0, 1.0, grading);
    out.nodesPerElement = box.nodesPerElement;
    std::vector<LocalIndex> renumber(box.numNodes());
    for (LocalIndex k = 0; k < box.numNodes(); ++k) {
      const double tu = std::tan(0.25 * M_PI * box.x(k)), tv = std::tan(0.25 * M_PI * box.y(k));
      const std::array<double, 3> c = patch == 0   ? std::array<double, 3>{1.0, tu, tv}
                                      : patch == 1 ? std::array<double, 3>{tv, 1.0, tu}
                                                   : std::array<double, 3>{tu, tv, 1.0};
      const double r = a + (b - a) * box.z(k), scale = r / std::hypot(c[0], c[1], c[2]);
      const std::array<double, 3> x{scale * c[0], scale * c[1], scale * c[2]};
      const std::array<long long, 3> key{std::llround(x[0] / quantum), std::llround(x[1] / quantum),
                                         std::llround(x[2] / quantum)};
      const auto [at, added] = merged.emplace(key, out.numNodes());
      if (added)
        out.coordinates.insert(out.coordinates.end(), x.begin(), x.end());
      renumber[k] = at->second;
    }
    const LocalIndex first = out.numElements();
    for (LocalIndex node : box.connectivity)
      out.connectivity.push_back(renumber[node]);
    const auto side = [&](const char *from, const std::string &to) {
      for (const BoundaryEdge &f : box.boundaries.at(from))
        out.boundaries[to].push_back({first + f.element, f.edge});
    };
    side("xmin", onU0[patch]);
    side("ymin", onV0[patch]);
    side("zmin", "inner");
    side("zmax", "outer");
  }
  out.elementRegion.assign(out.numElements(), 0);
  out.regionNames = {"body"};
  out.source = "generator " + gen;
  for (const auto &[surface, r] :
       {std::pair{std::string("inner"), a}, std::pair{std::string("outer"), b}}) {
    const std::vector<LocalIndex> nodes = out.nodesOf(surface);
    for (int i = 0; i < 3; ++i)
      out.nodeSets[surface + "_" + "xyz"[i]] = {closestNode3(
          out, nodes, std::array<double, 3>{i == 0 ? r : 0.0, i == 1 ? r : 0.0, i == 2 ? r : 0.0})};
  }
  out.finalizeIds();
  return out;
}

} // namespace mixcon
