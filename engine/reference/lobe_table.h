// A hemisphere light's specular lobe, precomputed once per gloss value (docs/physics.md,
// "Hemisphere lights"): the table shaders/lobe_lookup.h describes and looks up, built in double
// from reference/lobe_integrals and stored as float, the same data for both renderers (the GPU
// reads it from a storage buffer, the CPU reference through the same lookup in double), so they
// agree to float rounding.
//
// Building takes about a second of all cores per gloss value, so tables are kept: in memory for
// the process, and on disk in the folder METAMER_LOBE_CACHE names ("off": none), else
// $XDG_CACHE_HOME/metamer, else ~/.cache/metamer, one file per gloss value and table version
// (lobe-<version>-<gloss as hex bits>.bin), written under a temporary name and renamed. A file that
// is not exactly what this version writes (damaged — its checksum —, truncated, foreign) is ignored
// and rebuilt.
// Tests: reference/lobe_table_test.cpp; the certification against independent quadratures:
// tests/lobe_certification_test.cpp.
#pragma once

#include <glm/glm.hpp>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace metamer {

struct LobeTable {
    double gloss = 0.0;
    std::vector<glm::uvec4> data;  // LOBE_TABLE_UVEC4 entries, laid out as shaders/lobe_lookup.h says
};

// The table for a gloss in (0, 10⁶]: from this process, else the disk cache, else built and cached.
std::shared_ptr<const LobeTable> lobeTableFor(double gloss);

// Builds it (no cache), on `threads` threads (0: every core).
LobeTable buildLobeTable(double gloss, int threads = 0);

// The gloss's x1 warp, (k, 1/ln(1 + kπ/2)), as the lookup takes it (the GPU from the material block).
glm::dvec2 lobeWarp(double gloss);

// (I(n, v, u, N), I_unoccluded) by the shared lookup, in double.
glm::dvec2 lobeIntegrals(const LobeTable& table, const glm::dvec3& n, const glm::dvec3& v, const glm::dvec3& u);

// The disk cache's folder (empty: disabled) and a table's file name there.
std::filesystem::path lobeCacheFolder();
std::string lobeCacheFileName(double gloss);
// The table read from `file`, or nullptr when it is missing or not a valid table for `gloss`.
std::shared_ptr<LobeTable> readLobeTable(const std::filesystem::path& file, double gloss);
void writeLobeTable(const std::filesystem::path& file, const LobeTable& table);

}  // namespace metamer
