#include "python/errors.h"

#include "core/error.h"
#include "python/bindings.h"

#include <new>
#include <string>

namespace metamer::python {

namespace {

PyObject* errorType = nullptr;       // metamer.Error (RuntimeError)
PyObject* inputErrorType = nullptr;  // metamer.InputError (metamer.Error, ValueError)
PyObject* notFoundType = nullptr;    // metamer.NotFoundError (metamer.InputError, FileNotFoundError)
PyObject* warningType = nullptr;     // metamer.Warning (UserWarning)

// A warning the filters turned into an exception (warnings.simplefilter("error", metamer.Warning)),
// held until the call that warned returns, then raised in its place (raisePendingWarning). Guarded
// by the GIL. The engine warns from inside work that cannot unwind at that point (a worker thread,
// a parser mid-scene), so the call finishes and its result is dropped: nothing is half-made, and
// Python renders write no files.
PyObject *pendingType = nullptr, *pendingValue = nullptr, *pendingTraceback = nullptr;

// The engine's warnings (core/error.h) as Python warnings of category metamer.Warning, so a
// notebook shows them under the cell and `warnings` filters them. Called from whatever thread
// warns, usually with the GIL released by a render: it takes the GIL itself.
void warnInPython(const std::string& line) {
    py::gil_scoped_acquire gil;
    const std::string text = printableMessage(line.rfind("warning: ", 0) == 0 ? line.substr(9) : line);
    if (PyErr_WarnEx(warningType, text.c_str(), 1) < 0) {
        if (pendingType) {
            PyErr_Clear();  // the first one is raised
        } else {
            PyErr_Fetch(&pendingType, &pendingValue, &pendingTraceback);
        }
    }
}

// The engine's errors (core/error.h) as the module's exceptions, with the CLI's message.
void translate(std::exception_ptr p) {
    try {
        if (p) std::rethrow_exception(p);
    } catch (const NotFoundError& e) {
        PyErr_SetString(notFoundType, printableMessage(e.text()).c_str());
    } catch (const Error& e) {
        PyErr_SetString(e.code() == ExitCode::BadInput ? inputErrorType : errorType,
                        printableMessage(e.text()).c_str());
    } catch (const std::bad_alloc&) {
        PyErr_SetString(PyExc_MemoryError, "out of memory");
    }
}

}  // namespace

// A warning held from a call that then failed otherwise (an interrupt, an input error): dropped.
void discardPendingWarning() {
    Py_XDECREF(pendingType);
    Py_XDECREF(pendingValue);
    Py_XDECREF(pendingTraceback);
    pendingType = pendingValue = pendingTraceback = nullptr;
}

// After a call into the engine, with the GIL: the warning an "error" filter turned into an
// exception, raised now.
void raisePendingWarning() {
    if (!pendingType) return;
    PyErr_Restore(pendingType, pendingValue, pendingTraceback);
    pendingType = pendingValue = pendingTraceback = nullptr;
    throw py::error_already_set();
}

void bindErrors(py::module_& m) {
    errorType = PyErr_NewException("metamer.Error", PyExc_RuntimeError, nullptr);
    py::object bases = py::make_tuple(py::handle(errorType), py::handle(PyExc_ValueError));
    inputErrorType = PyErr_NewException("metamer.InputError", bases.ptr(), nullptr);
    m.attr("Error") = py::handle(errorType);
    m.attr("InputError") = py::handle(inputErrorType);
    // A named file that does not exist: `except FileNotFoundError` catches it as for open().
    py::object notFoundBases = py::make_tuple(py::handle(inputErrorType), py::handle(PyExc_FileNotFoundError));
    notFoundType = PyErr_NewException("metamer.NotFoundError", notFoundBases.ptr(), nullptr);
    m.attr("NotFoundError") = py::handle(notFoundType);
    warningType = PyErr_NewException("metamer.Warning", PyExc_UserWarning, nullptr);
    m.attr("Warning") = py::handle(warningType);
    setWarningSink(&warnInPython);
    py::register_exception_translator(&translate);
    // stderr again once the interpreter goes. Registered before the contexts' release
    // (python/render), so it runs after it: atexit runs last in, first out.
    py::module_::import("atexit").attr("register")(py::cpp_function([] { setWarningSink(nullptr); }));
}

}  // namespace metamer::python
