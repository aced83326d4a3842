#include "io/oiio_module.h"

#include <dlfcn.h>

#include <atomic>
#include <cstdlib>
#include <mutex>

namespace fs = std::filesystem;

namespace metamer {

namespace {

std::atomic<bool> loaded{false};

// The module beside the binary (or shared object) this code is linked into.
fs::path modulePath() {
    if (const char* env = std::getenv("METAMER_OIIO_MODULE"); env && *env) return env;
    Dl_info info{};
    if (dladdr(reinterpret_cast<void*>(&modulePath), &info) && info.dli_fname) {
        std::error_code ec;
        fs::path self = fs::canonical(info.dli_fname, ec);
        // Beside it, or one folder up: the Python package's CLI is metamer/bin/metamer, the module
        // beside it in metamer/ (build/python/metamer/ has a link to build/libmetamer_oiio.so).
        if (!ec && !fs::exists(self.parent_path() / "libmetamer_oiio.so", ec) &&
            fs::exists(self.parent_path().parent_path() / "libmetamer_oiio.so", ec))
            return self.parent_path().parent_path() / "libmetamer_oiio.so";
        if (!ec) return self.parent_path() / "libmetamer_oiio.so";
    }
    return "libmetamer_oiio.so";
}

}  // namespace

const OiioModuleApi& oiioModule() {
    static const OiioModuleApi* api = nullptr;
    static std::string error;
    static std::once_flag once;
    std::call_once(once, [] {
        const fs::path path = modulePath();
        // Never closed: canvases made by the module keep its code in use until exit.
        void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!handle) {
            error = fmt::format("cannot load the OpenImageIO module '{}' (built beside the metamer binary; "
                                "METAMER_OIIO_MODULE names another): {}",
                                path.string(), dlerror());
            return;
        }
        using Entry = const OiioModuleApi* (*)();
        auto entry = reinterpret_cast<Entry>(dlsym(handle, METAMER_OIIO_MODULE_ENTRY));
        const OiioModuleApi* a = entry ? entry() : nullptr;
        if (!a || a->version != kOiioModuleVersion) {
            error = fmt::format("the OpenImageIO module '{}' is {} (expected version {}): rebuild it", path.string(),
                                a ? fmt::format("version {}", a->version) : std::string("not a Metamer module"),
                                kOiioModuleVersion);
            return;
        }
        api = a;
        loaded = true;
    });
    if (!api) failRuntime("{}", error);
    return *api;
}

bool oiioModuleLoaded() { return loaded; }

RasterImage readWithOpenImageIO(const fs::path& path, const Where& where, const ImageHeaderCheck& check) {
    RasterImage header;
    if (std::string e = oiioModule().readFile(path.string(), header, true); !e.empty()) failInput(where, "{}", e);
    check(header);
    RasterImage img;
    if (std::string e = oiioModule().readFile(path.string(), img, false); !e.empty()) failInput(where, "{}", e);
    return img;
}

RasterImage readWithOpenImageIO(const std::vector<uint8_t>& bytes, const std::string& format, const Where& where,
                                const ImageHeaderCheck& check) {
    RasterImage header;
    if (std::string e = oiioModule().readMemory(bytes, format, header, true); !e.empty()) failInput(where, "{}", e);
    check(header);
    RasterImage img;
    if (std::string e = oiioModule().readMemory(bytes, format, img, false); !e.empty()) failInput(where, "{}", e);
    return img;
}

std::unique_ptr<ImageCanvas> makeImageCanvas(int width, int height, const fs::path& font) {
    return std::unique_ptr<ImageCanvas>(oiioModule().makeCanvas(width, height, font.string()));
}

}  // namespace metamer
