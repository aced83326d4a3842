#include "batch/sweep.h"
#include "core/file_reads.h"
#include "scene/json_values.h"

#include "core/csv_text.h"
#include "core/file_reads.h"
#include "core/json.h"
#include "io/exr_file.h"
#include "render/cube_formats.h"
#include "scene/json_values.h"
#include "scene/overrides.h"
#include "sensor/sensor_spec.h"

#include <algorithm>
#include <optional>
#include <fmt/ranges.h>

#include <fstream>
#include <sstream>

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

namespace metamer {

namespace {

enum class KeyType { String, Int, Bool, StringList, Number };

struct RenderKey {
    const char* name;
    KeyType type;
};

// The render settings a sweep may set, by the names `metamer render` gives them as flags.
const RenderKey kRenderKeys[] = {
    {"detector", KeyType::String},    {"adapt", KeyType::String},      {"display", KeyType::String},
    {"bits", KeyType::Int},           {"integration", KeyType::String}, {"xyz", KeyType::String},
    {"mode", KeyType::String},        {"grid", KeyType::String},        {"resample", KeyType::String},
    {"write", KeyType::StringList},   {"size", KeyType::String},        {"ssaa", KeyType::Int},
    {"half", KeyType::Bool},          {"compression", KeyType::String}, {"backend", KeyType::String},
    {"strict_coverage", KeyType::Bool}, {"format", KeyType::StringList},  // the cube's containers (render/cube_formats.h)
    // The simulated sensor (docs/sensor.md): a job that names one is captured after it renders.
    {"sensor", KeyType::String},      {"seed", KeyType::Int},           {"frames", KeyType::Int},
    {"exposure", KeyType::Number},
};

const RenderKey* findRenderKey(const std::string& name) {
    for (const RenderKey& k : kRenderKeys)
        if (name == k.name) return &k;
    return nullptr;
}

[[noreturn]] void unknownKey(const Where& where, const std::string& key, const std::vector<std::string>& allowed,
                             const char* what) {
    const std::string near = closestMatch(key, allowed);
    failInput(where, "unknown {} '{}'{}; expected one of: {}", what, key,
              near.empty() ? "" : fmt::format(" (did you mean '{}'?)", near), fmt::join(allowed, ", "));
}

// A render setting's value, checked for its type; "write" and "format" as lists of names ("png,xyz" or an array).
Json renderValue(const std::string& key, const Json& v, const Where& where) {
    const RenderKey* k = findRenderKey(key);
    if (!k) unknownKey(where, key, sweepRenderKeys(), "render setting");
    switch (k->type) {
        case KeyType::String:
            if (!v.is_string() || v.get<std::string>().empty())
                failInput(where, "expected a non-empty string, got {}", jsonTypeName(v));
            return v;
        case KeyType::Int:
            if (!v.is_number_integer()) failInput(where, "expected an integer, got {}", jsonTypeName(v));
            return v;
        case KeyType::Bool:
            if (!v.is_boolean()) failInput(where, "expected true or false, got {}", jsonTypeName(v));
            return v;
        case KeyType::Number:
            if (!v.is_number()) failInput(where, "expected a number, got {}", jsonTypeName(v));
            return v;
        case KeyType::StringList: {
            Json list = Json::array();
            auto add = [&](const std::string& s) {
                std::string item;
                std::istringstream in(s);
                while (std::getline(in, item, ','))
                    if (!item.empty()) list.push_back(item);
            };
            if (v.is_string()) {
                add(v.get<std::string>());
            } else if (v.is_array()) {
                for (const Json& e : v) {
                    if (!e.is_string()) failInput(where, "expected output names (strings), got {}", jsonTypeName(e));
                    add(e.get<std::string>());
                }
            } else {
                failInput(where, "expected a list of outputs (\"png,xyz\" or [\"png\", \"xyz\"]), got {}",
                          jsonTypeName(v));
            }
            if (list.empty()) failInput(where, "expected at least one output");
            return list;
        }
    }
    return v;
}

// A scene override from a sweep: "KEY=VALUE" as on the command line, or KEY and a JSON value.
std::string overrideText(const std::string& key, const Json& v) {
    if (v.is_string()) {
        // A string that would parse as JSON (e.g. "0.5", "true") is written quoted, so it stays a string.
        const std::string s = v.get<std::string>();
        return key + "=" + (Json::accept(s) ? v.dump() : s);
    }
    return key + "=" + v.dump();
}

std::vector<std::string> readOverrides(const Json& v, const Where& where) {
    std::vector<std::string> out;
    if (v.is_array()) {
        for (size_t i = 0; i < v.size(); ++i) {
            if (!v[i].is_string()) failInput(where.index(i), "expected \"KEY=VALUE\", got {}", jsonTypeName(v[i]));
            out.push_back(v[i].get<std::string>());
        }
    } else if (v.is_object()) {
        for (const auto& [k, value] : v.items()) out.push_back(overrideText(k, value));
    } else {
        failInput(where, "expected overrides: [\"KEY=VALUE\", ...] or {{\"KEY\": VALUE, ...}}, got {}",
                  jsonTypeName(v));
    }
    for (const std::string& o : out) parseOverride(o, where.str());  // KEY=VALUE syntax, early
    return out;
}

Json readRender(const Json& v, const Where& where) {
    if (!v.is_object()) failInput(where, "expected an object of render settings, got {}", jsonTypeName(v));
    Json out = Json::object();
    for (const auto& [k, value] : v.items()) out[k] = renderValue(k, value, where.child(k));
    return out;
}

void merge(Json& into, const Json& from) {
    for (const auto& [k, v] : from.items()) into[k] = v;
}

void requireKeys(const Json& obj, const Where& where, const std::vector<std::string>& allowed, const char* what) {
    for (const auto& [k, v] : obj.items())
        if (std::find(allowed.begin(), allowed.end(), k) == allowed.end()) unknownKey(where.child(k), k, allowed, what);
}

// A listed job: {"scene": ..., "set": ..., "render": ...}.
SweepJob readRow(const Json& row, const Where& where) {
    if (!row.is_object()) failInput(where, "expected a job object {{\"scene\": ..., \"set\": ..., \"render\": ...}}, got {}",
                                    jsonTypeName(row));
    requireKeys(row, where, {"scene", "set", "render"}, "job key");
    SweepJob j;
    j.where = where;
    j.origin = where.key;
    if (!row.contains("scene") || !row["scene"].is_string() || row["scene"].get<std::string>().empty())
        failInput(where.child("scene"), "every job needs \"scene\": the scene file (relative to the sweep's folder)");
    j.scene = row["scene"].get<std::string>();
    if (row.contains("set")) j.overrides = readOverrides(row["set"], where.child("set"));
    if (row.contains("render")) j.render = readRender(row["render"], where.child("render"));
    return j;
}

SweepAxis readAxis(const Json& a, const Where& where) {
    if (!a.is_object())
        failInput(where, "expected an axis {{\"set\": KEY or \"render\": NAME, \"values\": [...]}}, got {}",
                  jsonTypeName(a));
    requireKeys(a, where, {"name", "set", "render", "values"}, "axis key");
    SweepAxis x;
    x.where = where;
    const bool hasSet = a.contains("set"), hasRender = a.contains("render");
    if (hasSet == hasRender)
        failInput(where, "an axis varies either a scene key (\"set\": \"lights.0.spectrum\") or a render setting "
                  "(\"render\": \"detector\"): exactly one of the two");
    if (hasSet) {
        if (!a["set"].is_string() || a["set"].get<std::string>().empty())
            failInput(where.child("set"), "expected a scene key path, e.g. \"lights.0.spectrum\"");
        x.setKey = a["set"].get<std::string>();
    } else {
        if (!a["render"].is_string()) failInput(where.child("render"), "expected a render setting's name");
        x.renderKey = a["render"].get<std::string>();
        if (!findRenderKey(x.renderKey)) unknownKey(where.child("render"), x.renderKey, sweepRenderKeys(), "render setting");
    }
    if (a.contains("name") && (!a["name"].is_string() || a["name"].get<std::string>().empty()))
        failInput(where.child("name"), "expected the axis's name, a non-empty string; got {}", jsonTypeName(a["name"]));
    x.name = a.contains("name") ? a["name"].get<std::string>() : hasSet ? x.setKey : x.renderKey;
    if (!a.contains("values") || !a["values"].is_array() || a["values"].empty())
        failInput(where.child("values"), "expected a non-empty array of values");
    for (size_t i = 0; i < a["values"].size(); ++i) {
        const Json& v = a["values"][i];
        if (hasSet) {
            parseOverride(overrideText(x.setKey, v), where.child("values").index(i).str());
            x.values.push_back(v);
        } else {
            x.values.push_back(renderValue(x.renderKey, v, where.child("values").index(i)));
        }
    }
    return x;
}

std::string shortValue(const Json& v) {
    std::string s = v.is_string() ? v.get<std::string>() : v.dump();
    return s.size() > 40 ? s.substr(0, 37) + "..." : s;
}

Sweep readSweepJson(const fs::path& file, Sweep sweep) {
    // The scene reader's parser: duplicate keys, nesting beyond 64 levels and numbers beyond a
    // double are errors naming the line and key, as in a scene.
    const Json doc = json_read::parseJson(readWholeFile(file, Where{file.string()}, "sweep file"), file.string());
    const Where top{file.string()};
    if (!doc.is_object()) failInput(top, "expected a sweep object {{\"scenes\": [...], \"axes\": [...], ...}}");
    requireKeys(doc, top, {"scenes", "rows", "set", "render", "axes", "draws", "out"}, "sweep key");
    if (doc.contains("set")) sweep.common = readOverrides(doc["set"], top.child("set"));
    if (doc.contains("render")) sweep.commonRender = readRender(doc["render"], top.child("render"));
    if (doc.contains("out")) {
        if (!doc["out"].is_string() || doc["out"].get<std::string>().empty())
            failInput(top.child("out"), "expected the output folder (relative to the sweep's folder)");
        const fs::path out = doc["out"].get<std::string>();
        sweep.out = out.is_absolute() ? out : sweep.folder / out;
    }
    std::vector<SweepJob>& bases = sweep.bases;
    if (doc.contains("scenes")) {
        const Json& s = doc["scenes"];
        if (!s.is_array()) failInput(top.child("scenes"), "expected an array of scene files, got {}", jsonTypeName(s));
        for (size_t i = 0; i < s.size(); ++i) {
            if (!s[i].is_string() || s[i].get<std::string>().empty())
                failInput(top.child("scenes").index(i), "expected a scene file, got {}", jsonTypeName(s[i]));
            SweepJob j;
            j.scene = s[i].get<std::string>();
            j.where = top.child("scenes").index(i);
            j.origin = j.where.key;
            bases.push_back(j);
        }
    }
    if (doc.contains("rows")) {
        const Json& r = doc["rows"];
        if (!r.is_array()) failInput(top.child("rows"), "expected an array of jobs, got {}", jsonTypeName(r));
        for (size_t i = 0; i < r.size(); ++i) bases.push_back(readRow(r[i], top.child("rows").index(i)));
    }
    if (bases.empty()) failInput(top, "no jobs: give \"scenes\" (crossed with \"axes\") or \"rows\", or both");
    if (doc.contains("axes")) {
        const Json& a = doc["axes"];
        if (!a.is_array()) failInput(top.child("axes"), "expected an array of axes, got {}", jsonTypeName(a));
        for (size_t i = 0; i < a.size(); ++i) sweep.axes.push_back(readAxis(a[i], top.child("axes").index(i)));
    }
    if (doc.contains("draws")) {
        sweep.draws = readSweepDraws(doc["draws"], top.child("draws"), SpectrumLibrary());
        // Every listed value must make a valid override; drawn numbers always do.
        for (const SweepDrawValue& v : sweep.draws->values)
            for (size_t k = 0; k < v.choices.size(); ++k)
                parseOverride(overrideText(v.setKey, v.choices[k]), v.where.child("choose").index(k).str());
    }
    return sweep;
}

// A manifest's line as a job; one line past kMaxSweepJobs is refused before it is kept.
void addManifestJob(Sweep& sweep, SweepJob j) {
    if (sweep.bases.size() == kMaxSweepJobs)
        failInput(j.where, "more than {} jobs: a manifest this long would make more job folders than a dataset "
                  "should have (docs/batch.md, \"Limits\"); split it into several datasets", kMaxSweepJobs);
    sweep.bases.push_back(std::move(j));
}

Sweep readManifestJsonl(const fs::path& file, Sweep sweep) {
    std::ifstream in(file);
    if (!in) failInput(Where{file.string()}, "cannot open the manifest");
    std::string line;
    for (int n = 1; std::getline(in, line); ++n) {
        if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
        const Where where{file.string(), "", n};
        Json row;
        try {
            row = json_read::parseJson(line, file.string());
        } catch (const Error& e) {
            failInput(where, "not a JSON object on one line: {}", e.message());
        }
        SweepJob j = readRow(row, where);
        j.origin = fmt::format("line {}", n);
        addManifestJob(sweep, std::move(j));
    }
    if (sweep.bases.empty()) failInput(Where{file.string()}, "no jobs: the manifest has no lines");
    return sweep;
}

// A CSV cell as the JSON value of a render setting of that key's type.
Json cellValue(const std::string& key, const std::string& text, const Where& where) {
    const RenderKey* k = findRenderKey(key);
    if (k->type == KeyType::Int) {
        try {
            size_t used = 0;
            const long v = std::stol(text, &used);
            if (used == text.size()) return renderValue(key, Json(v), where);
        } catch (const std::exception&) {
        }
        failInput(where, "expected an integer, got '{}'", text);
    }
    if (k->type == KeyType::Bool) {
        if (text == "true" || text == "1") return true;
        if (text == "false" || text == "0") return false;
        failInput(where, "expected true or false, got '{}'", text);
    }
    return renderValue(key, Json(text), where);
}

Sweep readManifestCsv(const fs::path& file, Sweep sweep) {
    std::ifstream in(file);
    if (!in) failInput(Where{file.string()}, "cannot open the manifest");
    std::string line;
    std::vector<std::string> header;
    int n = 0;
    while (header.empty() && std::getline(in, line)) {
        ++n;
        // A UTF-8 byte-order mark (spreadsheets write one) is not part of the first column's name.
        if (n == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);
        if (line.find_first_not_of(" \t\r") != std::string::npos) header = splitCsvRecord(line, Where{file.string(), "", n});
    }
    const Where headerWhere{file.string(), "", n};
    if (header.empty()) failInput(Where{file.string()}, "no header line: expected scene,set:KEY,...,detector,...");
    int sceneColumn = -1;
    std::vector<std::string> allowed = {"scene", "set:KEY"};
    for (const std::string& k : sweepRenderKeys()) allowed.push_back(k);
    for (size_t c = 0; c < header.size(); ++c) {
        const std::string& h = header[c];
        for (size_t d = 0; d < c; ++d)
            if (header[d] == h)
                failInput(Where{file.string(), fmt::format("column {}", c + 1), n},
                          "'{}' is column {} too: each column once (a repeated one would silently win)", h, d + 1);
        if (h == "scene") {
            sceneColumn = int(c);
        } else if (h.rfind("set:", 0) == 0) {
            if (h.size() == 4) failInput(headerWhere, "column {}: 'set:' needs a scene key, e.g. set:lights.0.spectrum", c + 1);
        } else if (!findRenderKey(h)) {
            unknownKey(Where{file.string(), fmt::format("column {}", c + 1), n}, h, allowed, "column");
        }
    }
    if (sceneColumn < 0) failInput(headerWhere, "no 'scene' column");
    while (std::getline(in, line)) {
        ++n;
        if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
        const Where where{file.string(), "", n};
        const std::vector<std::string> f = splitCsvRecord(line, where);
        if (f.size() != header.size())
            failInput(where, "{} fields where the header has {} columns", f.size(), header.size());
        SweepJob j;
        j.where = where;
        j.origin = fmt::format("line {}", n);
        for (size_t c = 0; c < f.size(); ++c) {
            if (f[c].empty()) continue;
            const Where cell{file.string(), header[c], n};
            if (int(c) == sceneColumn) {
                j.scene = f[c];
            } else if (header[c].rfind("set:", 0) == 0) {
                const std::string o = header[c].substr(4) + "=" + f[c];
                parseOverride(o, cell.str());
                j.overrides.push_back(o);
            } else {
                j.render[header[c]] = cellValue(header[c], f[c], cell);
            }
        }
        if (j.scene.empty()) failInput(Where{file.string(), "scene", n}, "every job needs a scene file");
        addManifestJob(sweep, std::move(j));
    }
    if (sweep.bases.empty()) failInput(Where{file.string()}, "no jobs: the manifest has a header and no rows");
    return sweep;
}

// The sweep's job count, refused above kMaxSweepJobs with what makes it large (the product is
// checked for overflow factor by factor, so 2⁶⁴ jobs are refused, not wrapped around).
void checkJobCount(const Sweep& sweep) {
    size_t n = sweep.bases.size();
    double approx = double(n);
    bool over = n > kMaxSweepJobs;
    for (const SweepAxis& a : sweep.axes) {
        approx *= double(a.values.size());
        if (__builtin_mul_overflow(n, a.values.size(), &n) || n > kMaxSweepJobs) over = true;
    }
    if (sweep.draws) {
        approx *= double(sweep.draws->count);
        if (__builtin_mul_overflow(n, sweep.draws->count, &n) || n > kMaxSweepJobs) over = true;
    }
    if (!over) return;
    std::vector<std::string> factors{fmt::format("{} base job(s)", sweep.bases.size())};
    for (const SweepAxis& a : sweep.axes) factors.push_back(fmt::format("{} ({} values)", a.name, a.values.size()));
    if (sweep.draws) factors.push_back(fmt::format("{} draws", sweep.draws->count));
    failInput(Where{sweep.file.string(), sweep.axes.empty() ? "" : "axes"},
              "the sweep has {:.3g} jobs ({}), more than the limit of {} (docs/batch.md, \"Limits\"): split it "
              "into several sweeps or list fewer values",
              approx, fmt::join(factors, " × "), kMaxSweepJobs);
}

// Two jobs with the same settings would have the same id and folder: refused here, for every mode,
// naming both. Hashes first (16 bytes a job, not the settings' text), then the text where two meet.
void checkNoDuplicateJobs(const Sweep& sweep) {
    std::vector<std::pair<size_t, size_t>> hashes(sweep.size());
    for (size_t p = 0; p < hashes.size(); ++p) hashes[p] = {std::hash<std::string>{}(sweep.job(p).settings().dump()), p};
    std::sort(hashes.begin(), hashes.end());
    for (size_t i = 1; i < hashes.size(); ++i) {
        if (hashes[i].first != hashes[i - 1].first) continue;
        // Equal hashes: compare every earlier job of that hash with this one.
        const SweepJob b = sweep.job(hashes[i].second);
        for (size_t k = i; k-- > 0 && hashes[k].first == hashes[i].first;) {
            const SweepJob a = sweep.job(hashes[k].second);
            if (a.settings() != b.settings()) continue;
            failInput(Where{sweep.file.string(), b.where.key, b.where.line},
                      "jobs {} ({}) and {} ({}) render the same thing (same scene, overrides and render settings), "
                      "so they would share one job folder; list each job once",
                      hashes[k].second + 1, a.origin, hashes[i].second + 1, b.origin);
        }
    }
}

}  // namespace

size_t Sweep::size() const {
    size_t n = bases.size();
    for (const SweepAxis& a : axes) n *= a.values.size();  // checked when read (checkJobCount)
    if (draws) n *= draws->count;
    return n;
}

SweepJob Sweep::job(size_t position) const {
    size_t perBase = 1;
    for (const SweepAxis& a : axes) perBase *= a.values.size();
    const size_t drawCount = draws ? draws->count : 1;
    if (position >= bases.size() * perBase * drawCount)
        failRuntime("job {} of a sweep of {} jobs", position, bases.size() * perBase * drawCount);
    SweepJob j = bases[position / (perBase * drawCount)];
    j.overrides.insert(j.overrides.begin(), common.begin(), common.end());
    Json render = commonRender;
    merge(render, j.render);
    std::vector<std::string> picked;
    size_t rest = position % (perBase * drawCount) / drawCount;
    for (const SweepAxis& a : axes) {
        perBase /= a.values.size();
        const Json& v = a.values[rest / perBase];
        rest %= perBase;
        if (!a.setKey.empty())
            j.overrides.push_back(overrideText(a.setKey, v));
        else
            render[a.renderKey] = v;
        picked.push_back(a.name + "=" + shortValue(v));
        j.axes[a.name] = v;
    }
    if (draws) {
        // Drawn last, so they override the axes' values of the same key.
        const size_t d = position % drawCount;
        j.draw = d;
        j.axes["draw"] = d;
        for (const DrawnValue& v : drawValues(*draws, position)) {
            j.overrides.push_back(overrideText(v.setKey, v.value));
            j.axes[v.name] = v.value;
        }
        picked.push_back(fmt::format("draw {}", d));
    }
    j.render = render;
    if (!picked.empty()) j.origin += fmt::format(" × {}", fmt::join(picked, ", "));
    return j;
}

const std::vector<std::string>& sweepRenderKeys() {
    static const std::vector<std::string> keys = [] {
        std::vector<std::string> k;
        for (const RenderKey& r : kRenderKeys) k.push_back(r.name);
        return k;
    }();
    return keys;
}

Json SweepJob::settings() const {
    Json s = Json::object();
    s["scene"] = scene.lexically_normal().generic_string();
    s["set"] = overrides;
    Json r = Json::object();
    std::vector<std::string> keys;
    for (const auto& [k, v] : render.items()) keys.push_back(k);
    std::sort(keys.begin(), keys.end());
    for (const std::string& k : keys) r[k] = render[k];
    s["render"] = r;
    // A draw is a sample: two draws that happen to pick the same values are two jobs of the
    // dataset (drawn with replacement), not one job listed twice.
    if (draw) s["draw"] = *draw;
    return s;
}

Sweep readSweep(const fs::path& file) {
    requireRegularFile(file, Where{file.string()}, "sweep file");
    if (std::error_code ec; fs::file_size(file, ec) > kMaxTextFileBytes && !ec)
        failInput(Where{file.string()}, "the sweep file is over {} MiB", kMaxTextFileBytes >> 20);
    Sweep sweep;
    sweep.file = file;
    sweep.folder = fs::absolute(file).parent_path();
    const std::string ext = file.extension().string();
    if (ext == ".json")
        sweep = readSweepJson(file, sweep);
    else if (ext == ".jsonl")
        sweep = readManifestJsonl(file, sweep);
    else if (ext == ".csv")
        sweep = readManifestCsv(file, sweep);
    else
        failInput(Where{file.string()}, "expected a sweep file (.json) or a manifest (.jsonl, .csv), not '{}'", ext);
    checkJobCount(sweep);
    checkNoDuplicateJobs(sweep);
    return sweep;
}

RenderJob makeRenderJob(const Sweep& sweep, const SweepJob& j, const fs::path& outDir) {
    RenderJob job;
    job.scene = j.scene.is_absolute() ? j.scene : sweep.folder / j.scene;
    job.overrides = j.overrides;
    job.outDir = outDir;
    for (const auto& [key, v] : j.render.items()) {
        const Where where{j.where.file, j.where.key.empty() ? "render." + key : j.where.key + ".render." + key,
                          j.where.line};
        auto fail = [&](const std::string& expected) {
            failInput(where, "{}: '{}' for {}: expected {}", j.origin, v.is_string() ? v.get<std::string>() : v.dump(),
                      key, expected);
        };
        if (key == "detector") job.detector = v.get<std::string>();
        else if (key == "adapt") job.adaptation = v.get<std::string>();
        else if (key == "display") job.display = v.get<std::string>();
        else if (key == "integration") job.integration = v.get<std::string>();
        else if (key == "xyz") job.xyz = v.get<std::string>();
        else if (key == "mode") job.mode = v.get<std::string>();
        else if (key == "bits") {
            if (v != 8 && v != 16) fail("8 or 16");
            job.bits = v.get<int>();
        } else if (key == "grid") job.grid = Grid::parse(v.get<std::string>(), where);
        else if (key == "resample") job.resampling = parseResampling(v.get<std::string>(), where);
        else if (key == "write") job.write = v.get<std::vector<std::string>>();
        else if (key == "format") {
            parseCubeFormats(v.get<std::vector<std::string>>(), where);  // checked now, with the sweep's key
            job.format = v.get<std::vector<std::string>>();
        }
        else if (key == "size") {
            const std::string s = v.get<std::string>();
            // Digits only, each side 1 … 65536: "4294967304x8" must not wrap around to 8×8.
            auto side = [&](const std::string& t) {
                if (t.empty() || t.size() > 6 || t.find_first_not_of("0123456789") != std::string::npos) return 0;
                const int n = std::stoi(t);
                return n >= 1 && n <= 65536 ? n : 0;
            };
            const size_t cross = s.find_first_of("xX");
            const int w = cross == std::string::npos ? 0 : side(s.substr(0, cross));
            const int h = cross == std::string::npos ? 0 : side(s.substr(cross + 1));
            if (w == 0 || h == 0) fail("WIDTHxHEIGHT in pixels, each 1 to 65536, e.g. 64x64");
            job.overrides.push_back(fmt::format("camera.width={}", w));
            job.overrides.push_back(fmt::format("camera.height={}", h));
        } else if (key == "ssaa") {
            if (v < 1 || v > 4) fail("1 to 4");
            job.ssaa = v.get<int>();
        } else if (key == "half") job.half = v.get<bool>();
        else if (key == "compression") {
            if (!knownExrCompression(v.get<std::string>())) fail("an OpenEXR compression: " + exrCompressionNames());
            job.compression = v.get<std::string>();
        } else if (key == "backend") {
            if (v != "gpu" && v != "cpu") fail("gpu or cpu");
            job.backend = v == "cpu" ? Backend::Cpu : Backend::Gpu;
        } else if (key == "strict_coverage") {
            job.coverage = v.get<bool>() ? CoveragePolicy::Error : CoveragePolicy::ZeroWithWarning;
        } else if (key == "seed") {
            if (v < 0) fail("a whole number ≥ 0");
        } else if (key == "frames") {
            if (v < 1 || v > 100000) fail("1 to 100000");
        } else if (key == "exposure") {
            if (!(v.get<double>() > 0.0 && v.get<double>() <= 1e6)) fail("an exposure time in seconds, > 0 and at most 10⁶");
        }
    }
    if (j.render.contains("sensor")) {
        job.writeCube = true;  // the capture reads the cube; the scene's own write list stands otherwise
    } else {
        for (const char* k : {"seed", "frames", "exposure"})
            if (j.render.contains(k))
                failInput(Where{j.where.file, j.where.key.empty() ? std::string("render.") + k : j.where.key + ".render." + k,
                                j.where.line},
                          "{}: '{}' goes with 'sensor' (a simulated sensor's capture, docs/sensor.md)", j.origin, k);
    }
    return job;
}

std::optional<CaptureRequest> makeCaptureRequest(const Sweep& sweep, const SweepJob& j) {
    if (!j.render.contains("sensor")) return std::nullopt;
    CaptureRequest c;
    const std::string given = j.render["sensor"].get<std::string>();
    // A file is relative to the sweep's folder, as scenes are; a bare name is a library sensor.
    const fs::path asFile(given);
    c.sensor = namesSensorFile(given) ? (asFile.is_absolute() ? asFile : sweep.folder / asFile).string() : given;
    if (j.render.contains("seed")) c.seed = j.render["seed"].get<uint64_t>();
    if (j.render.contains("frames")) c.frames = j.render["frames"].get<int>();
    if (j.render.contains("exposure")) c.exposure = j.render["exposure"].get<double>();
    return c;
}

}  // namespace metamer
