// The readers of the material models (docs/scene-format.md, "Materials", "Transparent materials",
// "Paints and coatings"), one file each; scene/scene_json.cpp picks the model by its keys and calls
// its reader, which reads the keys with the shared context (scene/scene_reader.h). A new model's
// keys go in a file of its own beside these, and its tests in material_reader_<model>_test.cpp:
//   scene/material_reader_opaque.cpp       diffuse, specular, gloss, textures, fluorescence
//   scene/material_reader_transparent.cpp  thin sheets, absorbing media and dyes, glass slabs
//   scene/material_reader_paint.cpp        Kubelka–Munk layers, pigments, substrate, surface
// Tests: engine/scene/material_reader_opaque_test.cpp, material_reader_transparent_test.cpp and
// material_reader_paint_test.cpp (each its cases of SceneJsonBad, scene/scene_json_test_util.h),
// engine/scene/scene_donaldson_test.cpp, tests/bad_inputs_test.cpp (tests/bad-inputs/),
// tests/paints_test.cpp, tests/transparency_test.cpp.
#pragma once

#include "scene/scene_reader.h"

namespace metamer {

// An opaque material: "diffuse", "specular", "gloss", "textures" and "fluorescence" (an
// excitation/emission pair or a Donaldson matrix); with "layers" it is a paint (readPaint).
Material readOpaqueMaterial(SceneReader& r, Material m, const json_read::Json& v, const Where& w);

// A transparent material: a thin sheet ("transmittance"), an absorbing medium ("absorbance",
// "dyes") or a glass slab ("slab"). It reflects nothing but a slab's Fresnel reflection.
Material readTransparentMaterial(SceneReader& r, Material m, const json_read::Json& v, const Where& w);

// A paint's body reflectance: its "layers", "substrate" and "surface" into m.paint, refusing a
// "diffuse" or a diffuse texture beside them; m.diffuse becomes 1 (the layers give the reflectance).
void readPaint(SceneReader& r, Material& m, const json_read::Json& v, const Where& w);

}  // namespace metamer
