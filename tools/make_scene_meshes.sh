#!/usr/bin/env bash
# Remakes the mesh files the shipped scenes read (scenes/meshes/) from their Gmsh sources, with
# Debian's gmsh: the layered abdominal wall as binary Gmsh 4.1 with its three physical groups, and
# the liver-like organ as a closed STL surface (xcut tetrahedralizes it when the scene loads).
set -euo pipefail
cd "$(dirname "$0")/../scenes/meshes"
gmsh -3 abdominal_wall.geo -format msh41 -bin -o abdominal_wall.msh
gmsh -2 liver_lobe.geo -format stl -bin -o liver_lobe.stl
