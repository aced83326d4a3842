#include "python/arguments.h"

#include "core/error.h"

#include <fmt/format.h>

#include <cmath>

namespace metamer::python {

namespace fs = std::filesystem;

const char* typeName(const py::handle& x) { return Py_TYPE(x.ptr())->tp_name; }

bool isPath(const py::handle& x) {
    return py::isinstance<py::str>(x) || py::isinstance<py::bytes>(x) ||
           py::isinstance(x, py::module_::import("os").attr("PathLike"));
}

// A path argument: str, bytes or os.PathLike, read as os.fsencode reads it (a str in the file
// system's encoding, undecodable bytes kept as they were); anything else is a TypeError naming
// the argument. (py::str would have read b'x.json' as the text "b'x.json'".)
fs::path pathOf(const py::handle& x, const char* name) {
    if (!isPath(x))
        throw py::type_error(fmt::format("{}: expected a path (str, bytes or os.PathLike), got {}", name, typeName(x)));
    const std::string bytes = py::module_::import("os").attr("fsencode")(x).cast<py::bytes>();
    // The OS would read the path only up to the NUL: another file than the one named.
    if (bytes.find('\0') != std::string::npos) failInput(Where{"", name}, "the path holds a NUL byte");
    return fs::path(bytes);
}

// An integer argument: an int or a numpy integer (not a bool, not a float), within [lo, hi];
// else a TypeError or an InputError naming it, not pybind11's list of signatures.
long long integer(const py::handle& x, const char* name, long long lo, long long hi) {
    if (py::isinstance<py::bool_>(x) || !py::hasattr(x, "__index__"))
        throw py::type_error(fmt::format("{}: expected an integer, got {}", name, typeName(x)));
    const py::int_ i = py::module_::import("operator").attr("index")(x);
    int overflow = 0;
    const long long v = PyLong_AsLongLongAndOverflow(i.ptr(), &overflow);
    if (overflow || v < lo || v > hi)
        failInput(Where{"", name}, "{} is out of range; expected {} … {}", py::str(py::handle(i)).cast<std::string>(), lo, hi);
    return v;
}

uint64_t unsignedInteger(const py::handle& x, const char* name) {
    if (py::isinstance<py::bool_>(x) || !py::hasattr(x, "__index__"))
        throw py::type_error(fmt::format("{}: expected an integer, got {}", name, typeName(x)));
    const py::int_ i = py::module_::import("operator").attr("index")(x);
    const unsigned long long v = PyLong_AsUnsignedLongLong(i.ptr());
    if (PyErr_Occurred()) {
        PyErr_Clear();
        failInput(Where{"", name}, "{} is out of range; expected 0 … 2⁶⁴ − 1", py::str(py::handle(i)).cast<std::string>());
    }
    return v;
}

// A number argument (int, float or a numpy number; not a bool), finite; else a TypeError or an
// InputError naming it.
double number(const py::handle& x, const char* name) {
    if (py::isinstance<py::bool_>(x) || py::isinstance<py::str>(x) || !py::hasattr(x, "__float__"))
        throw py::type_error(fmt::format("{}: expected a number, got {}", name, typeName(x)));
    const double v = PyFloat_AsDouble(x.ptr());
    if (PyErr_Occurred()) throw py::error_already_set();
    if (!std::isfinite(v)) failInput(Where{"", name}, "expected a finite number, got {}", v);
    return v;
}

std::optional<double> optionalNumber(const py::handle& x, const char* name) {
    if (x.is_none()) return std::nullopt;
    return number(x, name);
}

// A text argument (a str; None for "not given" where allowed); else a TypeError naming it.
std::string text(const py::handle& x, const char* name) {
    if (!py::isinstance<py::str>(x)) throw py::type_error(fmt::format("{}: expected a str, got {}", name, typeName(x)));
    try {
        return x.cast<std::string>();
    } catch (const py::cast_error&) {
        PyErr_Clear();
        failInput(Where{"", name}, "the text is not valid Unicode (a lone surrogate)");
    }
}

// An optional text argument: None for the scene's or the default choice; '' is refused, as the
// CLI refuses an empty flag value (`--grid ''`), rather than read as "not given".
std::string optionalText(const py::handle& x, const char* name) {
    if (x.is_none()) return {};
    std::string s = text(x, name);
    if (s.empty()) failInput(Where{"", name}, "empty; give a value, or None for the default");
    return s;
}

// A scene (or an override's value) given as Python objects, as JSON for the scene parser: dicts
// with str keys, lists, tuples and numpy arrays (a spectrum's values), str, bool, int, float,
// None and numpy scalars. What JSON cannot hold is refused at its key path: NaN and infinities
// (json.dumps would write NaN, which the parser refuses without saying where), other types, and
// nesting deeper than the parser takes (a dict that holds itself).
nlohmann::json toJson(const py::handle& v, const std::string& at, int depth) {
    constexpr int kDeepest = 64;
    if (depth > kDeepest)
        failInput(Where{"", at}, "nested deeper than {} levels (a dict or list that holds itself?)", kDeepest);
    // Kept for the process (a static py::object would be released after the interpreter is gone).
    static const py::handle numpyGeneric = py::object(py::module_::import("numpy").attr("generic")).release();
    static const py::handle numpyArray = py::object(py::module_::import("numpy").attr("ndarray")).release();
    if (v.is_none()) return nullptr;
    if (py::isinstance<py::bool_>(v)) return v.cast<bool>();
    if (py::isinstance(v, numpyArray) || py::isinstance(v, numpyGeneric))
        return toJson(v.attr("tolist")(), at, depth);  // Python numbers, lists of them
    if (py::isinstance<py::int_>(v)) {
        int overflow = 0;
        const long long i = PyLong_AsLongLongAndOverflow(v.ptr(), &overflow);
        if (!overflow) return i;
        failInput(Where{"", at}, "{} is out of range for a scene's numbers", py::str(v).cast<std::string>());
    }
    if (py::isinstance<py::float_>(v)) {
        const double d = v.cast<double>();
        if (!std::isfinite(d)) failInput(Where{"", at}, "{} is not a number a scene holds (JSON has no NaN or infinity)", d);
        return d;
    }
    if (py::isinstance<py::str>(v)) return text(v, at.c_str());
    if (py::isinstance<py::dict>(v)) {
        nlohmann::json o = nlohmann::json::object();
        for (auto [key, value] : v.cast<py::dict>()) {
            if (!py::isinstance<py::str>(key))
                throw py::type_error(fmt::format("{}: a key must be a str, got {} {}", at, typeName(key),
                                                 py::repr(key).cast<std::string>()));
            const std::string k = text(key, at.c_str());
            o[k] = toJson(value, at + "." + k, depth + 1);
        }
        return o;
    }
    if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) {
        nlohmann::json a = nlohmann::json::array();
        size_t i = 0;
        for (const py::handle& item : v) a.push_back(toJson(item, at + "." + std::to_string(i++), depth + 1));
        return a;
    }
    throw py::type_error(fmt::format("{}: a {} is not something a scene holds (dict, list, str, number, bool or None)",
                                     at, typeName(v)));
}

std::vector<std::string> stringList(const py::handle& value, const char* name) {
    if (value.is_none()) return {};
    if (py::isinstance<py::str>(value)) {
        // "cube,xyz": the CLI's comma-separated form.
        std::vector<std::string> out;
        std::string s = value.cast<std::string>();
        size_t start = 0;
        while (start <= s.size()) {
            size_t comma = s.find(',', start);
            std::string item = s.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
            if (!item.empty()) out.push_back(item);
            if (comma == std::string::npos) break;
            start = comma + 1;
        }
        return out;
    }
    // A sequence of str; not bytes, whose items would be read as numbers.
    if (py::isinstance<py::bytes>(value) || !py::hasattr(value, "__iter__"))
        throw py::type_error(fmt::format("{}: expected a str or a sequence of str, got {}", name, typeName(value)));
    std::vector<std::string> out;
    for (const py::handle& item : value) out.push_back(text(item, name));
    return out;
}

// overrides: ["KEY=VALUE", ...] as --set takes them, or {key: value} (values as JSON).
std::vector<std::string> overrideList(const py::handle& value) {
    if (value.is_none()) return {};
    if (py::isinstance<py::dict>(value)) {
        std::vector<std::string> out;
        for (auto [k, v] : value.cast<py::dict>()) {
            const std::string key = text(k, "overrides");
            const std::string value = py::isinstance<py::str>(v) ? text(v, ("overrides." + key).c_str())
                                                                 : toJson(v, "overrides." + key).dump();
            out.push_back(key + "=" + value);
        }
        return out;
    }
    return stringList(value, "overrides");
}

}  // namespace metamer::python
