#include "render/ground_truth.h"

#include "core/json.h"
#include "core/timing.h"
#include "reference/cpu_renderer.h"
#include "render/spectral_pass.h"

namespace metamer {

GroundTruthImages GroundTruth::images() const {
    GroundTruthImages t;
    t.reflectance = reflectance.empty() ? nullptr : reflectance.data();
    t.illumination = illumination.empty() ? nullptr : illumination.data();
    t.geometry = geometry.mask.empty() ? nullptr : &geometry;
    t.legend = legend;
    return t;
}

namespace {

std::vector<float> gpuMap(const GroundTruthJob& job, SurfaceQuantity quantity) {
    SpectralPassOptions po;
    po.ssaa = job.ssaa;
    po.readback = job.readback;
    po.quantity = quantity;
    SpectralPass pass(*job.context, *job.scene, *job.spectra, po);
    return pass.render().data;
}

}  // namespace

GroundTruth renderGroundTruth(const GroundTruthJob& job, const OutputFiles& files) {
    const auto start = Clock::now();
    GroundTruth t;
    // One reference renderer for its maps and the geometry: it solves the interreflection only
    // for the CPU's illumination map (the reflectance and the geometry maps need no indirect light).
    ReferenceOptions ro;
    ro.ssaa = job.ssaa;
    ro.interreflection = job.backend == Backend::Cpu && files.illumination;
    ReferenceRenderer reference(*job.scene, *job.spectra, ro);
    auto map = [&](SurfaceQuantity q) {
        if (job.backend == Backend::Gpu) return gpuMap(job, q);
        reference.setQuantity(q);
        return reference.render().cube.data;
    };
    if (files.reflectance) t.reflectance = map(SurfaceQuantity::Reflectance);
    if (files.illumination) t.illumination = map(SurfaceQuantity::Illumination);
    if (files.groundTruth()) t.geometry = reference.geometryMaps();  // the mask comes with every map
    if (files.ids) t.legend = groundTruthLegend(*job.scene, job.ssaa);
    t.ms = msSince(start);
    return t;
}

std::string groundTruthLegend(const Scene& scene, int ssaa) {
    nlohmann::ordered_json j;
    j["scene"] = scene.file.string();
    j["background"] = -1;
    j["sample"] = ssaa > 1 ? "each pixel's central sample of its ssaa × ssaa, not an average" : "each pixel's centre";
    nlohmann::ordered_json objects = nlohmann::ordered_json::array(), materials = nlohmann::ordered_json::array();
    for (size_t i = 0; i < scene.meshes.size(); ++i)
        objects.push_back({{"id", i}, {"name", scene.meshes[i].name}, {"material", scene.meshes[i].material}});
    for (size_t i = 0; i < scene.materials.size(); ++i)
        materials.push_back({{"id", i}, {"name", scene.materials[i].name}});
    j["objects"] = objects;
    j["materials"] = materials;
    return j.dump(2) + "\n";
}

}  // namespace metamer
