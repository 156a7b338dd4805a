// A liver-like organ surface, in millimetres as organ models often are: an ellipsoid of 160 x 100 x
// 60 mm fused with a thinner lobe, written as a triangulated STL surface that xcut tetrahedralizes
// with TetGen when the scene loads (scenes/organ_from_surface.json, "units": "mm").
// Regenerate: tools/make_scene_meshes.sh
SetFactory("OpenCASCADE");
Sphere(1) = {0, 0, 0, 1};
Dilate {{0, 0, 0}, {80, 50, 30}} { Volume{1}; }
Sphere(2) = {0, 0, 0, 1};
Dilate {{0, 0, 0}, {45, 35, 12}} { Volume{2}; }
Translate {70, 20, -8} { Volume{2}; }
BooleanUnion{ Volume{1}; Delete; }{ Volume{2}; Delete; }
Mesh.CharacteristicLengthMax = 18;
