#include "render/render_setup.h"

#include "scene/scene_json.h"
#include "scene/scene_white.h"

namespace metamer {

std::unique_ptr<LoadedScene> loadJobScene(const RenderJob& job) {
    auto l = std::make_unique<LoadedScene>();
    LoadOptions loadOptions;
    loadOptions.allowOutsidePaths = job.allowOutsidePaths;
    loadOptions.grid = job.grid;
    l->scene = job.sceneText ? loadSceneFromString(*job.sceneText, job.scene, l->library, job.overrides, loadOptions)
                             : loadScene(job.scene, l->library, job.overrides, loadOptions);
    // The render grid: the job's, else the scene's, with the scene's resampling rule unless the
    // job names one. The scene itself stays as read.
    l->grid = l->scene.grid;
    if (job.grid) {
        l->grid = *job.grid;
        l->grid.resampling = l->scene.grid.resampling;
    }
    if (job.resampling) l->grid.resampling = *job.resampling;
    l->spectra = resampleScene(l->scene, l->grid, job.coverage);
    l->representation =
        makeRepresentation(parseMode(job.mode, Where{"", "--mode"}), l->grid, l->library, &l->spectra);
    l->rendered = represent(l->spectra, l->representation, l->scene);
    return l;
}

TonemapPlan makeScenePlan(const TonemapSettings& settings, const Scene& scene, const SceneOnGrid& spectra,
                          const SpectrumLibrary& library, const Representation* representation) {
    return makeTonemapPlan(settings, spectra.grid, referenceWhite(scene, spectra, library), library,
                           representation ? displayChannels(*representation) : DisplayChannels{});
}

TonemapPlan makeJobTonemapPlan(const RenderJob& job, const LoadedScene& loaded, const TonemapSettings& settings) {
    const Scene& scene = loaded.scene;
    // Names given in the scene are reported against the scene's output block.
    Where sceneOut = scene.output.where.file.empty() ? Where{scene.file.string(), "output"} : scene.output.where;
    try {
        return makeScenePlan(settings, scene, loaded.spectra, loaded.library, &loaded.representation);
    } catch (const Error& e) {
        bool detectorFromScene = !job.detector && scene.output.detector;
        // A csv: detector's own errors name its file and line; when the scene chose it, say where.
        bool inDetectorFile = e.code() == ExitCode::BadInput && !e.where().file.empty() &&
                              e.where().file != scene.file.string();
        if (inDetectorFile && (detectorFromScene || job.detector)) {
            Where inFile = e.where();
            inFile.key.clear();  // the file and line; the key is where the detector was chosen
            throw Error(e.code(), detectorFromScene ? sceneOut.child("detector") : Where{"", "--detector"},
                        inFile.str() + ": " + e.message());
        }
        if (e.where().key == "--absolute") {
            // Absolute XYZ with a non-CIE-1931 detector: blame the xyz choice where it was made.
            Where at = !job.xyz && scene.output.xyz ? sceneOut.child("xyz") : Where{"", "--xyz"};
            throw Error(e.code(), at, e.message());
        }
        const std::string& key = e.where().key;
        bool fromScene = (detectorFromScene && key == "--detector") ||
                         (!job.display && scene.output.display && key == "--display") ||
                         (!job.integration && scene.output.integration && key == "--integration");
        if (!fromScene) throw;
        throw Error(e.code(), sceneOut.child(key.substr(2)), e.message());
    }
}

vk::ContextOptions jobContextOptions(const RenderJob& job) {
    vk::ContextOptions co = vk::contextOptionsFromEnvironment();
    co.validation = co.validation || job.validation;
    if (!job.device.empty()) {
        co.device = job.device;
        co.deviceFrom = "--device";
    }
    co.verbose = job.verbose;
    return co;
}

}  // namespace metamer
