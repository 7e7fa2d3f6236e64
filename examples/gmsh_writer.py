"""Writes Gmsh 4.1 ASCII mesh files (the subset mixcon reads) for the example mesh scripts
(examples/bracket_3d/make_bracket_mesh.py, examples/nafems_le10/make_le10_mesh.py)."""


def write_msh(path, physical_names, entities, coordinates, blocks):
    """Writes `path`:
    - physical_names: [(dim, tag, name)];
    - entities: ((points, curves, surfaces, volumes), [the $Entities lines after the counts]);
    - coordinates: one "x y z" string per node, for the tags 1..N in order (one node block, on
      volume entity 1);
    - blocks: [(dim, entity, Gmsh element type, [node tag lists])], elements numbered from 1 in
      this order."""
    counts, entity_lines = entities
    n = len(coordinates)
    out = ["$MeshFormat", "4.1 0 8", "$EndMeshFormat", "$PhysicalNames", str(len(physical_names))]
    out += [f'{dim} {tag} "{name}"' for dim, tag, name in physical_names]
    out += ["$EndPhysicalNames", "$Entities", " ".join(str(c) for c in counts)]
    out += list(entity_lines)
    out += ["$EndEntities", "$Nodes", f"1 {n} 1 {n}", f"3 1 0 {n}"]
    out += [str(t) for t in range(1, n + 1)] + list(coordinates)
    count = sum(len(b[3]) for b in blocks)
    out += ["$EndNodes", "$Elements", f"{len(blocks)} {count} 1 {count}"]
    number = 0
    for dim, entity, gmsh_type, conn in blocks:
        out.append(f"{dim} {entity} {gmsh_type} {len(conn)}")
        for c in conn:
            number += 1
            out.append(" ".join(str(x) for x in [number] + list(c)))
    out.append("$EndElements")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")
