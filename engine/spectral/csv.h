// Spectrum files: plain CSV, one sample per line, `wavelength_nm,value[,value...]`.
// An optional header line (first non-comment line that is not numeric) names the columns;
// lines starting with '#' and blank lines are ignored. Errors name the file and line.
#pragma once

#include "spectral/bispectral.h"
#include "spectral/spectrum.h"

#include <filesystem>
#include <string>
#include <vector>

namespace metamer {

struct SpectralTable {
    std::vector<std::string> columnNames;  // header names of the value columns (may be empty)
    std::vector<double> wavelengths_nm;
    std::vector<std::vector<double>> columns;  // columns[c][row]
};

// Reads a table with at least `minColumns` value columns; validates wavelengths (finite,
// strictly increasing) and values (finite).
SpectralTable readSpectralTable(const std::filesystem::path& path, size_t minColumns = 1);

// Reads a single-spectrum CSV (exactly one value column).
Spectrum readSpectrumCsv(const std::filesystem::path& path);

// Reads a Donaldson matrix (docs/scene-format.md, "Donaldson matrix files"): a header row whose
// first field is a label (any text, or empty) followed by the emission wavelengths λout in nm,
// then one row per excitation wavelength λin: `λin,D(λin, λout₁),D(λin, λout₂),...` in nm⁻¹.
// '#' comment lines and blank lines are skipped. Every error names the file, and the line and
// column where one cell is at fault.
BispectralMatrix readBispectralCsv(const std::filesystem::path& path);

}  // namespace metamer
