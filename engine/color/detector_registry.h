// Which detector a name means: one table of makers, from a spec ("cie1931", "camera:<name>",
// "film:<name>", "csv:<path>") to a Detector on a grid. A new kind of detector (a sensor) is one
// row of that table in detector_registry.cpp. The Detector type itself is color/detector.h.
// Tests: color/detector_test.cpp.
#pragma once

#include "color/detector.h"
#include "spectral/library.h"

#include <string>
#include <vector>

namespace metamer {

// Makes a detector on `grid`. Specs:
//   "cie1931", "cie1964"  the CIE 1931 2° and 1964 10° observers (spectra/observers), X Y Z;
//                         zero outside 360–830 nm
//   "camera:<name>"       spectra/cameras/<name>.csv (wavelength_nm,r,g,b), R G B
//   "film:<name>"         the three layers' sensitivities of spectra/film/<name>.json, blue green red
//   "csv:<path>"          a user table wavelength_nm,ch1[,ch2...] with 1–8 channels; header names
//                         become channel names ("ch1"... without a header); the path is absolute or
//                         relative to the current directory. Zero outside its data (with a warning
//                         when the data do not reach every band centre of the grid).
// Library data are resampled onto the grid like every other spectrum (docs/physics.md,
// "Resampling"). An unknown spec is an input error at `where` with a suggestion and the list of
// known detectors.
Detector makeDetector(const std::string& spec, const SpectrumLibrary& library, const Grid& grid,
                      Integration integration, const Where& where);

// Every built-in detector spec, for help text and suggestions: observers, then cameras, then films.
std::vector<std::string> detectorNames(const SpectrumLibrary& library);

}  // namespace metamer
