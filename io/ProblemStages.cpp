// The stages section of the problem file: a load history of ordered stages, each with the values
// its loads, prescribed displacements and obstacle drives reach at its end, its own load factors
// and iteration settings (io/ProblemReader.hpp). Data flow: io (input side).
#include <io/ProblemReader.hpp>

#include <algorithm>
#include <set>
#include <string>
#include <vector>

namespace mixcon::detail {

namespace {

constexpr const char *kComponents[3] = {"ux", "uy", "uz"};

/// The iteration keys of `steps` a stage may set for itself.
constexpr const char *kIterationKeys[] = {"iteration", "tolerance", "residual_tolerance",
                                          "max_iterations", "max_cuts"};

/// The stage's load factors: `increments` (1/n ... 1) or `load_factors`, increasing in (0, 1]
/// and ending at 1 (the stage reaches the values it names).
std::vector<double> stageLoadFactors(const YamlItem &s) {
  if (s.has("increments") && s.has("load_factors"))
    s.fail("give 'increments' or 'load_factors', not both");
  std::vector<double> f;
  if (s.has("load_factors")) {
    const YamlItem l = s["load_factors"];
    l.requireSequence();
    if (l.node.size() == 0)
      l.fail("needs at least one load factor");
    for (std::size_t k = 0; k < l.node.size(); ++k) {
      const double v = l.at(k).number();
      if (!(v > (f.empty() ? 0.0 : f.back())) || v > 1.0)
        l.at(k).fail("the load factors of a stage increase within (0, 1] (0: where the stage "
                     "starts, 1: the values it names)");
      f.push_back(v);
    }
    if (f.back() != 1.0)
      l.fail("the last load factor of a stage must be 1 (the stage ends at the values it names)");
    return f;
  }
  const int n = s.has("increments") ? s["increments"].integer() : 1;
  if (n < 1 || n > 1000000)
    s["increments"].fail("must be between 1 and 1000000");
  for (int k = 1; k <= n; ++k)
    f.push_back(static_cast<double>(k) / n);
  return f;
}

/// The iteration settings of a stage: the problem's (steps) with the stage's own keys.
NonlinearOptions stageIterations(const YamlItem &s, const Problem &p) {
  NonlinearOptions n = p.nonlinear;
  for (const char *key : kIterationKeys)
    if (s.has(key) && !p.model.geometricNonlinearity && p.contact.empty())
      s[key].fail(std::string(key) +
                  " applies to geometrically nonlinear or contact analyses (a linear body reaches "
                  "each increment in one solve)");
  readIterationKeys(s, n);
  return n;
}

/// A stage's `contact:` entry: the drive of a rigid obstacle at the stage's end.
DriveSpec stageDrive(const YamlItem &c, const Problem &p) {
  c.allowOnly({"boundary", "drive"});
  DriveSpec d;
  d.line = c.line();
  const YamlItem b = c.required("boundary");
  d.boundary = b.string();
  const auto rigidOn = [&](const ContactSpec &o) {
    return o.type != "node_to_segment" && o.boundary == d.boundary;
  };
  const auto obstacle = std::find_if(p.contact.begin(), p.contact.end(), rigidOn);
  if (obstacle == p.contact.end()) {
    std::string names;
    for (const auto &o : p.contact)
      if (o.type != "node_to_segment")
        names += (names.empty() ? "'" : ", '") + o.boundary + "'";
    b.fail("no rigid obstacle of the contact section acts on '" + d.boundary + "' (" +
           (names.empty() ? std::string("the problem has none: only rigid obstacles are driven")
                          : "obstacles on: " + names) +
           ")");
  }
  if (std::count_if(p.contact.begin(), p.contact.end(), rigidOn) > 1)
    b.fail("several rigid obstacles act on '" + d.boundary +
           "'; a stage cannot tell which one it drives");
  readDrive(c.required("drive"), d.displacement, d.force, d.forceDriven);
  for (int i = 0; i < 2; ++i)
    if (d.forceDriven[i] != obstacle->forceDriven[i])
      c["drive"].fail(std::string("component ") + (i == 0 ? "x" : "y") + " of the obstacle on '" +
                      d.boundary + "' is driven by a " +
                      (obstacle->forceDriven[i] ? "force" : "displacement") +
                      " (contact section); a stage gives its end value the same way");
  return d;
}

} // namespace

void readStages(const YamlItem &top, Problem &p) {
  if (!top.has("stages"))
    return;
  const YamlItem list = top["stages"];
  list.requireSequence();
  if (list.node.size() == 0)
    list.fail("needs at least one stage");
  if (p.hybrid)
    list.fail("a hybrid run takes its steps from its measurement file; it has no stages");
  if (top.has("verification"))
    top["verification"].fail("verification checks one proportional load against its closed "
                             "form; a problem with stages has none");
  if (top.has("steps"))
    for (const char *key : {"increments", "load_factors"})
      if (top["steps"].has(key))
        top["steps"][key].fail("with stages, each stage gives its own increments or "
                               "load_factors (steps keeps the iteration settings)");

  // Which components are held, stage by stage (a release must free a held component).
  const int dim = p.mesh.dim();
  std::vector<char> held(static_cast<std::size_t>(p.mesh.numNodes()) * dim, 0);
  const auto hold = [&](const DirichletSpec &d) {
    const std::optional<double> *v[3] = {&d.ux, &d.uy, &d.uz};
    for (LocalIndex n : p.mesh.nodesOf(d.target))
      for (int c = 0; c < dim; ++c)
        if (*v[c])
          held[static_cast<std::size_t>(n) * dim + c] = 1;
  };
  for (const auto &d : p.dirichlet)
    hold(d);

  std::set<std::string> names;
  for (std::size_t k = 0; k < list.node.size(); ++k) {
    const YamlItem s = list.at(k);
    s.allowOnly({"name", "increments", "load_factors", "boundary_conditions", "loads", "contact",
                 "iteration", "tolerance", "residual_tolerance", "max_iterations", "max_cuts"});
    StageSpec stage;
    stage.line = s.line();
    stage.name = s.has("name") ? s["name"].string() : "stage " + std::to_string(k + 1);
    if (!names.insert(stage.name).second)
      (s.has("name") ? s["name"] : s).fail("stage name '" + stage.name + "' given twice");
    stage.loadFactors = stageLoadFactors(s);
    stage.nonlinear = stageIterations(s, p);
    if (s.has("boundary_conditions")) {
      const YamlItem bcs = s["boundary_conditions"];
      bcs.requireSequence();
      for (std::size_t i = 0; i < bcs.node.size(); ++i) {
        const YamlItem b = bcs.at(i);
        DirichletSpec d = readDirichlet(b, p.mesh, true);
        if (b.has("release")) {
          if (k == 0)
            b["release"].fail("the first stage has nothing to release yet (its supports are "
                              "the top-level boundary_conditions and its own)");
          // release: [ux, ...] names held components; release: true frees what is held there.
          const bool named = !b["release"].node.IsScalar();
          bool any = false;
          for (LocalIndex n : p.mesh.nodesOf(d.target))
            for (int c = 0; c < dim; ++c) {
              const bool h = held[static_cast<std::size_t>(n) * dim + c] != 0;
              any = any || (d.release[c] && h);
              if (named && d.release[c] && !h)
                b["release"].fail(std::string("releases ") + kComponents[c] + " of node " +
                                  std::to_string(p.mesh.nodeId(n)) + " on '" + d.target +
                                  "', which no earlier entry holds");
            }
          if (!any)
            b["release"].fail("nothing on '" + d.target + "' is held: nothing to release");
        }
        stage.dirichlet.push_back(d);
      }
      // A component is released or prescribed by a stage, not both (the outcome would depend on
      // the order of the entries).
      for (std::size_t i = 0; i < stage.dirichlet.size(); ++i)
        for (std::size_t j = 0; j < stage.dirichlet.size(); ++j) {
          const DirichletSpec &r = stage.dirichlet[i], &v = stage.dirichlet[j];
          const std::optional<double> *values[3] = {&v.ux, &v.uy, &v.uz};
          for (int c = 0; c < dim; ++c) {
            if (!r.release[c] || !*values[c])
              continue;
            const auto rn = p.mesh.nodesOf(r.target), vn = p.mesh.nodesOf(v.target);
            for (LocalIndex n : rn)
              if (std::binary_search(vn.begin(), vn.end(), n))
                bcs.at(j).fail(std::string("prescribes ") + kComponents[c] + " of node " +
                               std::to_string(p.mesh.nodeId(n)) + ", which the entry at line " +
                               std::to_string(r.line) + " releases in the same stage");
          }
        }
      // Within a stage, the same rule as at the top: one value per node component. A stage's
      // entry sets the end value of a support the top level (or an earlier stage) holds.
      checkDirichletConflicts(p.mesh, stage.dirichlet, p.file, p.mesh.warnings);
      for (const auto &d : stage.dirichlet) {
        for (int c = 0; c < dim; ++c)
          if (d.release[c])
            for (LocalIndex n : p.mesh.nodesOf(d.target))
              held[static_cast<std::size_t>(n) * dim + c] = 0;
        hold(d);
      }
    }
    if (s.has("loads")) {
      const YamlItem loads = s["loads"];
      loads.requireSequence();
      for (std::size_t i = 0; i < loads.node.size(); ++i) {
        const LoadSpec l = readLoad(loads.at(i), p);
        // A pressure keeps its kind (follower or dead) through the history.
        std::vector<const std::vector<LoadSpec> *> earlier{&p.loads, &stage.loads};
        for (const auto &st : p.stages)
          earlier.push_back(&st.loads);
        for (const auto *list : earlier)
          for (const auto &e : *list)
            if (e.kind == LoadKind::Pressure && l.kind == LoadKind::Pressure &&
                e.target == l.target && e.follower != l.follower)
              loads.at(i).fail("the pressure on '" + l.target + "' is a " +
                               (e.follower ? "follower" : "dead") + " load at line " +
                               std::to_string(e.line) +
                               "; a stage changes its value, not its "
                               "kind");
        stage.loads.push_back(l);
      }
    }
    if (s.has("contact")) {
      const YamlItem c = s["contact"];
      c.requireSequence();
      for (std::size_t i = 0; i < c.node.size(); ++i) {
        const DriveSpec d = stageDrive(c.at(i), p);
        for (const auto &e : stage.drives)
          if (e.boundary == d.boundary)
            c.at(i).fail("the obstacle on '" + d.boundary + "' is already driven at line " +
                         std::to_string(e.line) + " of this stage");
        stage.drives.push_back(d);
      }
    }
    p.stages.push_back(stage);
  }
}

} // namespace mixcon::detail
