// Three layers of an abdominal wall, 60 x 40 mm: muscle 10 mm, fat 5 mm, skin 2 mm, in metres.
// Each layer is a physical volume, read by xcut as a named region (scenes/layered_incision.json).
// Regenerate: tools/make_scene_meshes.sh
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.06, 0.04, 0.010};
Box(2) = {0, 0, 0.010, 0.06, 0.04, 0.005};
Box(3) = {0, 0, 0.015, 0.06, 0.04, 0.002};
Coherence;
Physical Volume("muscle") = {1};
Physical Volume("fat") = {2};
Physical Volume("skin") = {3};
Mesh.CharacteristicLengthMax = 0.004;
