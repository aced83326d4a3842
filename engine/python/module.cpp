// `import metamer`: the engine for Python (docs/python.md). A thin binding: metamer.render runs
// the same render job as `metamer render`, with the outputs kept in memory (RenderJob::capture),
// and hands the arrays to numpy without a copy; Render.save writes the CLI's files from them;
// metamer.compare and metamer.load_cube call the compare and io layers. One Vulkan context per
// device choice is made on first use and kept for the process (as metamer batch keeps one for its
// jobs), so a call does not pay the device start-up. Errors are metamer.InputError (what the CLI
// exits 2 on; also a ValueError) or metamer.Error, carrying the CLI's message.
//
// This file makes the module and calls each area's registration (python/bindings.h); it keeps
// only the two probes of the machine the package's own code asks for (the spectra library, a
// usable Vulkan device). Tests: tests/python/test_module.py (pytest).
#include "python/bindings.h"
#include "spectral/library.h"
#include "vk/check.h"
#include "vk/context.h"

#include <pybind11/pybind11.h>

#include <fmt/format.h>

#include <string>

namespace py = pybind11;
using namespace metamer;

PYBIND11_MODULE(_metamer, m) {
    m.doc() = "Metamer: full-spectral rendering of spectral radiance cubes (docs/python.md)";
    python::bindErrors(m);
    m.attr("__version__") = METAMER_VERSION;
    python::bindRenderClass(m);
    python::bindRender(m);
    python::bindCompare(m);
    python::bindCapture(m);
    python::bindCamera(m);
    m.def("_spectra_root", [] { return SpectrumLibrary::defaultRoot().string(); },
          "The spectra library a render reads when METAMER_SPECTRA is not set: the package's own copy "
          "when installed (tests)");
    // What keeps this machine from rendering ("" when a usable Vulkan device exists), for the
    // package's check at import (engine/python/metamer/__init__.py): no driver, or no device.
    m.def("_vulkan_problem", []() -> std::string {
        py::gil_scoped_release release;
        VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
        app.apiVersion = VK_API_VERSION_1_1;
        VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
        ici.pApplicationInfo = &app;
        VkInstance instance = VK_NULL_HANDLE;
        if (VkResult r = vkCreateInstance(&ici, nullptr, &instance); r != VK_SUCCESS)
            return fmt::format("the Vulkan loader found no driver (vkCreateInstance returned {})", vk::resultName(r));
        const auto devices = vk::Context::listDevices(instance);
        vkDestroyInstance(instance, nullptr);
        if (devices.empty()) return "the Vulkan loader found no device";
        for (const auto& d : devices)
            if (d.score > 0) return "";
        return fmt::format("no Vulkan device is usable ({} found; `metamer devices` lists them)", devices.size());
    });
    python::bindKubelkaMunk(m);
}
