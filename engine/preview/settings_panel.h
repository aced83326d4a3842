// The live controls of one view: each light's spectrum (from the library) and scale, each
// transparent material's filter or medium spectrum and dye concentrations, the detector,
// chromatic adaptation, display model, representation mode and grid step, and interreflection
// (on or off, its element size). They edit a copy of
// the view's RenderJob; the session hands the edited job to View::update(), which re-renders.
// Tests: engine/preview/preview_settings_test.cpp.
#pragma once

#include "preview/view.h"
#include "spectral/library.h"

#include <string>
#include <vector>

namespace metamer::preview {

// Sets KEY=VALUE in `overrides`, replacing an earlier override of the same key (so repeated
// edits do not pile up) or appending it.
void setOverride(std::vector<std::string>& overrides, const std::string& key, const std::string& value);

// The grid step's choices: the grid from `grid.start_nm` with this step, ending at the last band
// centre that is not past `grid.end_nm`.
Grid gridWithStep(const Grid& grid, double step_nm);

// The --set keys the panel edits on a transparent material: its filter spectrum
// ("materials.NAME.transmittance"), its medium's absorbance, or dye i's concentration.
std::string transmittanceKey(const Material& m);
std::string absorbanceKey(const Material& m);
std::string dyeConcentrationKey(const Material& m, size_t dye);
// The --set keys the panel edits on a paint: a layer's thickness, and a layer's pigment's
// concentration ("materials.NAME.layers.L.pigments.P.concentration").
std::string layerThicknessKey(const Material& m, size_t layer);
std::string pigmentConcentrationKey(const Material& m, size_t layer, size_t pigment);

// The interreflection switch: off removes an "interreflection=true" the panel added (the file has
// no such key) or adds "interreflection=false"; on removes an "interreflection=false" (the file's
// own settings come back) or adds "interreflection=true". Element size edits are
// "interreflection.element_size" overrides (setOverride).
void setInterreflection(std::vector<std::string>& overrides, bool on);

class SettingsPanel {
public:
    explicit SettingsPanel(const SpectrumLibrary& library);
    // Draws the controls for `view` into the current ImGui window. Returns true when the user
    // changed something; `job` then holds the new settings (a copy of view.job() with the edit).
    bool draw(const View& view, RenderJob& job);

private:
    std::vector<std::string> lightSpectra_;  // library illuminants
    std::vector<std::string> filterSpectra_, mediumSpectra_;  // library filters/ and media/
    std::vector<std::string> detectors_;
};

}  // namespace metamer::preview
