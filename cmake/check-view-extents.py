#!/usr/bin/env python3
"""Fails (exit 1) when a Kokkos::View extent is spelled with a function-local constant.

nvcc 13 miscompiles such extents inside function templates: after
`constexpr int kDim = Elem::kDim;`, `View<double **[kDim * kDim]> a; View<double **[kDim]> b;`
gave b the extent of a (4 instead of 2 for a 2D element). The host then launches a kernel
instantiation the device code does not have: "invalid resource handle" or a wrong result on the
GPU, nothing on CPU builds (docs/gpu.md, "nvcc 13 restrictions"). Extents are spelled from the
element or a namespace-scope constant instead (Voigt<Elem::kDim>::kSize, Elem::kDim, kStress of
FieldOps). A local constant is one declared `constexpr` in an indented line up to 150 lines above
the View, in the same file. Run by ctest (repo.view_extents, label unit).
Usage: cmake/check-view-extents.py [root] (default: the repository of this script)."""
import os
import re
import sys

root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..")
declaration = re.compile(r"^\s+(?:static\s+)?constexpr\s+(?:int|long|unsigned|std::size_t|"
                         r"LocalIndex|auto)\s+(.*);")
extent = re.compile(r"View<[^;]*?\[([^\]]+)\]")
bad = []
for folder in ("core", "mesh", "kernels", "solver", "contact", "io", "apps", "tests", "bench"):
    for base, _, names in os.walk(os.path.join(root, folder)):
        for name in sorted(names):
            if not name.endswith((".cpp", ".hpp")):
                continue
            path = os.path.join(base, name)
            local = {}
            with open(path, encoding="utf-8") as f:
                for number, line in enumerate(f, 1):
                    m = declaration.match(line)
                    if m:
                        for part in m.group(1).split(","):
                            local[part.split("=")[0].strip()] = number
                    for e in extent.finditer(line):
                        # Qualified names (Elem::kDim, Voigt<...>::kSize) are not local.
                        text = re.sub(r"[\w>]+::\w+", "", e.group(1))
                        for word in set(re.findall(r"\b[A-Za-z_]\w*\b", text)):
                            if word in local and number - local[word] <= 150:
                                bad.append(f"  {os.path.relpath(path, root)}:{number}: [{e.group(1)}]"
                                           f" uses {word}, a local constant of line {local[word]}")
if bad:
    print("check-view-extents: View extents from function-local constants (nvcc 13 can give them\n"
          "another extent; spell them from the element, e.g. Elem::kDim):", file=sys.stderr)
    print("\n".join(bad), file=sys.stderr)
    sys.exit(1)
print("check-view-extents: no View extent uses a function-local constant")
