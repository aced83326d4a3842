// The Python module's errors and warnings: metamer.Error (a RuntimeError), metamer.InputError
// (also a ValueError: what the CLI exits 2 on), metamer.NotFoundError (also a FileNotFoundError),
// each carrying the CLI's message, and the engine's warnings as Python warnings of category
// metamer.Warning (a UserWarning). A warning that a filter turns into an error is held while the
// engine works and raised when the call returns (docs/python.md, "Behaviour").
// Tests: tests/python/test_module.py (messages equal to the CLI's, warnings, warnings as errors).
#pragma once

#include <pybind11/pybind11.h>

namespace metamer::python {

namespace py = pybind11;

// Around each call into the engine, with the GIL: drop a warning held from an earlier call that
// failed otherwise (before), and raise the one an "error" filter made (after).
void discardPendingWarning();
void raisePendingWarning();

}  // namespace metamer::python
