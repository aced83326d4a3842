#include "app/render_flags.h"

#include "app/cli_checks.h"

namespace metamer {

CLI::Option* addRenderFlag(CLI::App* c, const std::string& name, std::string& value) {
    return c->add_option("--" + name, value, renderSettingHelp(name));
}

CLI::Option* addRenderFlag(CLI::App* c, const std::string& name, std::vector<std::string>& value) {
    CLI::Option* o = c->add_option("--" + name, value, renderSettingHelp(name));
    return name == "set" ? o->take_all() : o->delimiter(',');
}

CLI::Option* addRenderFlag(CLI::App* c, const std::string& name, bool& value) {
    return c->add_flag("--" + name + (name == "verbose" ? ",-v" : ""), value, renderSettingHelp(name));
}

void addRenderFlags(CLI::App* c, RenderSettings& s, unsigned groups) {
    auto in = [&](unsigned group) { return (groups & group) != 0; };
    if (in(kSpectralFlags)) {
        addRenderFlag(c, "grid", s.grid);
        addRenderFlag(c, "resample", s.resample);
    }
    if (in(kSceneFlags)) addRenderFlag(c, "set", s.overrides);
    if (in(kFileFlags))
        addRenderFlag(c, "backend", s.backend)->check(CLI::IsMember({"gpu", "cpu"}))->capture_default_str();
    if (in(kSamplingFlags))
        c->add_option("--ssaa", s.ssaa, renderSettingHelp("ssaa"))->check(CLI::Range(1, 4))->capture_default_str();
    if (in(kFileFlags)) {
        addRenderFlag(c, "half", s.half);
        addRenderFlag(c, "compression", s.compression)->capture_default_str();
        addRenderFlag(c, "strict-coverage", s.strictCoverage);
        addRenderFlag(c, "readback", s.readback)->check(CLI::IsMember({"auto", "map", "copy"}))->capture_default_str();
    }
    if (in(kDisplayFlags)) {
        addRenderFlag(c, "detector", s.detector);
        addRenderFlag(c, "adapt", s.adapt);
        addRenderFlag(c, "display", s.display);
        c->add_option("--bits", s.bits, renderSettingHelp("bits"))->check(CLI::IsMember({8, 16}));
        addRenderFlag(c, "integration", s.integration);
    }
    if (in(kFileFlags))
        c->add_option("--memory-budget", s.memoryBudgetMiB, renderSettingHelp("memory-budget"))->check(positiveNumber("MiB"));
    if (in(kSpectralFlags)) addRenderFlag(c, "mode", s.mode)->capture_default_str();
    if (in(kFileFlags)) {
        addRenderFlag(c, "xyz", s.xyz);
        addRenderFlag(c, "write", s.write);
        addRenderFlag(c, "format", s.format);
        addRenderFlag(c, "no-png", s.noPng);
        c->add_option("--frames", s.frames, renderSettingHelp("frames"))->check(CLI::Range(1, 1000));
    }
    if (in(kDeviceFlags)) {
        addRenderFlag(c, "validation", s.validation);
        addRenderFlag(c, "device", s.device);
        addRenderFlag(c, "verbose", s.verbose);
    }
    if (in(kSceneFlags)) addRenderFlag(c, "allow-outside-paths", s.allowOutsidePaths);
}

}  // namespace metamer
