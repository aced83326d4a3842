// The Python module's arguments as the engine takes them: paths (str, bytes, os.PathLike), integers,
// numbers, text, lists of text, `overrides`, and scene dicts as JSON. A wrong type is a TypeError
// and a wrong value a metamer.InputError, each starting with the argument's name (`ssaa: expected
// an integer, got str`), not pybind11's list of signatures (docs/python.md, "Behaviour").
// Tests: tests/python/test_module.py (hostile arguments, paths, scene dicts, numpy values).
#pragma once

#include "core/json.h"

#include <pybind11/pybind11.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace metamer::python {

namespace py = pybind11;

// The Python type's name of x, for messages ("str", "NoneType", "numpy.ndarray").
const char* typeName(const py::handle& x);

// str, bytes or os.PathLike.
bool isPath(const py::handle& x);

// A path argument, read as os.fsencode reads it; a NUL byte is an InputError.
std::filesystem::path pathOf(const py::handle& x, const char* name);

// An int or a numpy integer (not a bool, not a float) within [lo, hi].
long long integer(const py::handle& x, const char* name, long long lo, long long hi);
uint64_t unsignedInteger(const py::handle& x, const char* name);

// An int, float or numpy number (not a bool), finite; None → nullopt for the optional form.
double number(const py::handle& x, const char* name);
std::optional<double> optionalNumber(const py::handle& x, const char* name);

// A str; the optional form takes None as "not given" ("" back) and refuses "".
std::string text(const py::handle& x, const char* name);
std::string optionalText(const py::handle& x, const char* name);

// A scene (or an override's value) as JSON, refused at its key path `at` where JSON cannot hold it.
nlohmann::json toJson(const py::handle& v, const std::string& at, int depth = 0);

// "a,b" or a sequence of str (None: empty); `overrides` as ["KEY=VALUE", ...] or {key: value}.
std::vector<std::string> stringList(const py::handle& value, const char* name);
std::vector<std::string> overrideList(const py::handle& value);

}  // namespace metamer::python
