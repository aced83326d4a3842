// The scene model: plain data, as loaded and validated from a scene file. Geometry is already in
// world space (triangles, metres); spectra are as read (not yet on the grid). Both renderers
// consume this; neither reaches back into JSON.
// Tests: engine/scene/scene_json_test.cpp.
#pragma once

#include "core/error.h"
#include "spectral/bispectral.h"
#include "spectral/dielectric.h"
#include "spectral/grid.h"
#include "spectral/spectrum.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace metamer {

// A spectrum together with the key path it came from, for warnings about coverage.
struct SceneSpectrum {
    Spectrum spectrum;
    SpectrumKind kind = SpectrumKind::Reflectance;
    Where where;
};

struct Camera {
    enum class Projection { Perspective, Orthographic };
    Projection projection = Projection::Perspective;
    glm::dvec3 position{0, 0, 5};
    glm::dvec3 target{0, 0, 0};
    glm::dvec3 up{0, 1, 0};
    double fov_y_deg = 35.0;  // perspective: full vertical field of view
    double height_m = 2.0;    // orthographic: height of the view in metres (width from aspect)
    int width = 512;          // pixels
    int height = 512;
};

struct Light {
    // Hemisphere: a uniform environment, radiance L(λ) from every direction ω with ω·up > 0 (a
    // sky; a ground is a hemisphere whose up points down). Not occluded (docs/physics.md).
    enum class Type { Ambient, Directional, Point, Hemisphere };
    Type type = Type::Directional;
    // Directional: the direction the light travels (towards the scene), normalized.
    glm::dvec3 direction{0, -1, 0};
    // Point: position in metres.
    glm::dvec3 position{0, 0, 0};
    // Hemisphere: the unit vector towards the middle of the hemisphere it shines from.
    glm::dvec3 up{0, 1, 0};
    // spectrum × scale is: ambient and directional, irradiance E(λ) in W·m⁻²·nm⁻¹;
    // point, radiant intensity I(λ) in W·sr⁻¹·nm⁻¹; hemisphere, radiance L(λ) in W·sr⁻¹·m⁻²·nm⁻¹.
    SceneSpectrum spectrum;
    double scale = 1.0;
    // Directional and point lights: whether what stands between the light and a surface blocks
    // it (shadows; docs/physics.md, "Shadows"). Ambient and hemisphere lights are never blocked.
    bool shadows = true;
    bool castsShadows() const { return shadows && (type == Type::Directional || type == Type::Point); }
    std::string name;  // "lights.1"
};

// A Donaldson matrix D(λin, λout) as read (nm⁻¹, spectral/bispectral.h), its scale factor and
// the key path it came from.
struct SceneMatrix {
    BispectralMatrix matrix;
    double scale = 1.0;  // multiplies D
    Where where;         // "materials.NAME.fluorescence.matrix"
};

// Either the rank-one form (excitation, emission, quantum yield) or a Donaldson matrix: when
// `matrix` is set, the other members are unused.
struct Fluorescence {
    SceneSpectrum excitation;  // absorptance a(λ), 0..1
    SceneSpectrum emission;    // emission shape, any scale; normalized to unit integral
    double quantum_yield = 1.0;
    std::optional<SceneMatrix> matrix;
};

// A texture as read from its file (scene/texture.h), before it meets the render grid. Texel
// (i, j) covers [i, i+1]×[j, j+1] in pixels; row 0 is the top of the image, which is where
// texture coordinate v = 0 lies (glTF's convention: u right, v down).
struct Texture {
    enum class Kind {
        Spectral,  // reflectance per wavelength (a reflective spectral EXR, T.<λ>nm channels)
        Rgb,       // linear RGB reflectance (sRGB-encoded files are decoded on load), up-sampled
                   // to spectra on the grid (color/rgb_upsampling.h)
        Normal,    // tangent-space unit normals (x right, y up in the image, z out of the surface)
        Scalar,    // one number ≥ 0 per texel (a paint layer's thickness factor), turned into
                   // spectra on the grid by the material that uses it (scene/scene_on_grid)
    };
    Kind kind = Kind::Spectral;
    std::filesystem::path file;
    Where where;  // the scene key it came from, for messages
    int width = 0, height = 0, channels = 0;
    std::vector<double> wavelengths_nm;  // Spectral: one per channel, increasing
    std::vector<float> texels;           // width × height × channels, row 0 at the top
};

// Textures of a material: indices into Scene::textures, -1 for none.
struct MaterialTextures {
    int diffuse = -1;   // multiplies ρd (the material's diffuse spectrum is the tint; 1 if unset)
    int specular = -1;  // multiplies ρs
    int normal = -1;    // perturbs the shading normal (a normal map, or a bump map converted to one)
    bool any() const { return diffuse >= 0 || specular >= 0 || normal >= 0; }
};

struct Material {
    std::string name;
    SceneSpectrum diffuse;    // ρd(λ), Lambertian reflectance factor
    SceneSpectrum specular;   // ρs(λ), Blinn–Phong lobe weight (normal-incidence reflectance)
    double gloss = 0.0;       // Blinn–Phong exponent n (≥ 0)
    std::optional<Fluorescence> fluorescence;
    MaterialTextures textures;
    // Transparent materials (docs/physics.md, "Transparent objects") reflect nothing and change what
    // is seen through them, band by band. A thin sheet (a gel, a printed transparency) multiplies by
    // its transmittance T(λ) at each surface crossed; an absorbing medium fills a closed mesh and
    // multiplies by 10^(−a(λ)·ℓ) over the path length ℓ inside it (Beer–Lambert).
    std::optional<SceneSpectrum> transmittance;  // T(λ), 0..1 per crossing
    // a(λ), decadic absorbance per metre (m⁻¹): the "absorbance" spectrum plus each dye's molar
    // absorptivity ε(λ) (L·mol⁻¹·cm⁻¹) × concentration c (mol·L⁻¹) × 100 cm/m.
    std::optional<SceneSpectrum> absorbance;
    struct Dye {
        SceneSpectrum absorptivity;  // ε(λ), L·mol⁻¹·cm⁻¹
        double concentration = 0.0;  // c, mol·L⁻¹
    };
    std::vector<Dye> dyes;
    // A plane-parallel dielectric slab on a surface (a window, a glass sheet, filter glass): its
    // faces reflect and transmit by Fresnel's equations with n(λ), the reflections inside add
    // incoherently, and the glass absorbs along the refracted path (docs/physics.md, "Transparent objects").
    struct Slab {
        RefractiveIndex ior;
        std::string iorSource;  // how the scene gave n: "1.52", "N-BK7", "sellmeier", "cauchy", "table"
        Where iorWhere;
        double thickness_m = 0.0;
        std::optional<SceneSpectrum> absorbance;  // decadic, per metre of path inside
    };
    std::optional<Slab> slab;
    // A layered material (docs/physics.md, "Paints and coatings"): Kubelka–Munk films over a
    // substrate, whose reflectance — computed once per scene on the grid — is the body (diffuse)
    // reflectance under the material's specular and fluorescence terms. `diffuse` then holds 1.
    struct Paint {
        struct Pigment {
            std::string name;         // "pigments/rutile_white", or "" for an inline K/S pair
            SceneSpectrum k, s;       // per unit concentration, m⁻¹
            double concentration = 0; // cᵢ: K += cᵢkᵢ, S += cᵢsᵢ (two-constant mixing)
            Where where;
        };
        struct Layer {
            std::optional<SceneSpectrum> K, S;  // the layer's own (a binder, or a whole measured layer), m⁻¹
            std::vector<Pigment> pigments;
            double thickness_m = 0.0;  // X; INFINITY: an opaque layer (R∞), the bottom one only
            int thicknessMap = -1;     // Scene::textures (Kind::Scalar): X × the texel's value
            Where where;
        };
        std::vector<Layer> layers;  // bottom-up
        std::optional<SceneSpectrum> substrate;  // R_g(λ); or:
        int substrateMaterial = -1;              // an earlier material's diffuse reflectance
        Where substrateWhere;
        // Saunderson's correction: k1 and k2 given, or from n (k1 = ((n−1)/(n+1))², k2 integrated).
        struct Surface {
            std::optional<RefractiveIndex> ior;
            std::string iorSource;
            double k1 = 0.0, k2 = 0.0;
            Where where;
        };
        std::optional<Surface> surface;
        int thicknessMap() const {
            for (const Layer& l : layers)
                if (l.thicknessMap >= 0) return l.thicknessMap;
            return -1;
        }
    };
    std::optional<Paint> paint;
    // A self-luminous surface (a lamp's diffuser, a lit panel): radiance L_e(λ) = spectrum × scale
    // in W·sr⁻¹·m⁻²·nm⁻¹, the same in every direction of its front (the side its normal points to;
    // a closed mesh's outside), added to what it reflects. It lights the other surfaces through
    // interreflection only (docs/physics.md, "Interreflection"); without it, it is only seen.
    struct Emitter {
        SceneSpectrum spectrum;
        double scale = 1.0;
        Where where;  // the "emitted_radiance" key
    };
    std::optional<Emitter> emitter;

    bool isPaint() const { return paint.has_value(); }
    // Textures read with the object's texture coordinates (a paint's thickness map among them).
    bool needsTextureCoordinates() const { return textures.any() || (paint && paint->thicknessMap() >= 0); }
    bool isFilter() const { return transmittance.has_value(); }
    bool isMedium() const { return absorbance.has_value() || !dyes.empty(); }
    bool isSlab() const { return slab.has_value(); }
    bool isTransparent() const { return isFilter() || isMedium() || isSlab(); }

    bool hasSpecular() const {
        return !(specular.spectrum.isConstant() && *specular.spectrum.constant == 0.0);
    }
};

// A triangle mesh in world space. Normals are per vertex (unit length); the shading normal is
// their barycentric interpolation, renormalized.
struct Mesh {
    std::vector<glm::dvec3> positions;
    std::vector<glm::dvec3> normals;
    // Texture coordinates per vertex (u right, v down the image; repeat outside [0, 1]) and
    // tangents (xyz: the direction of increasing u, w = ±1: the bitangent cross(n, t)·w points up
    // the image, i.e. towards decreasing v). Either may be empty: no UVs, no textures; no
    // tangents, no normal mapping.
    std::vector<glm::dvec2> uvs;
    std::vector<glm::dvec4> tangents;
    std::vector<uint32_t> indices;  // 3 per triangle, counter-clockwise seen from the normal side
    uint32_t material = 0;          // index into Scene::materials
    std::string name;               // "objects.2" (+ " (assets/teapot.gltf)")
    // Closed and wound outwards: every edge (vertices welded by position) shared by exactly two
    // triangles, in opposite directions, and a positive signed volume. Its back faces are seen
    // only from inside, so the GPU path may cull them when the camera is outside (scene/shapes.h).
    bool closed = false;
};

// The scene's "output" block: how the display path should see the scene. Every field is optional
// (command-line flags override it); names are checked where they are used, with `where`.
struct OutputSettings {
    std::optional<std::string> detector, adaptation, display, integration, xyz;  // xyz: relative|absolute
    std::optional<int> bits;
    std::optional<std::vector<std::string>> write;  // of "cube", "png", "xyz", "responses" and the ground truth's
                                                    // "reflectance", "illumination", "ids", "depth", "normal"
    std::optional<std::vector<std::string>> format;  // the cube's containers: exr, hdf5[:gzip[:N]], envi[:bsq|bil|bip]
    Where where;                                     // the "output" key
};

// The scene's "interreflection" block (docs/scene-format.md, "Interreflection"): light that bounces
// between the diffuse surfaces, solved once per scene by radiosity/scene_radiosity.h.
struct Interreflection {
    std::optional<double> elementSize_m;  // no element edge longer; default: the objects' bounding-box diagonal / 24
    double tolerance = 1e-4;              // the solve's bound on the remaining error, relative to the largest radiosity
    int maxElements = 6000;               // refused beyond (the form factors take elements² × 8 bytes)
    Where where;                          // the "interreflection" key
    int refine = 0;                       // passes of refinement where the indirect light changes fast (0: none)
    double refineThreshold = 0.05;        // an edge is bisected when interpolating H along it misses its midpoint by more (relative)
};

struct Scene {
    std::filesystem::path file;  // the scene file, for messages
    OutputSettings output;
    std::optional<Interreflection> interreflection;  // absent: light scatters once, as always
    Grid grid;
    Camera camera;
    std::vector<Light> lights;
    std::vector<Material> materials;
    std::vector<Texture> textures;
    std::vector<Mesh> meshes;

    bool hasFluorescence() const;
    bool hasSpecular() const;
    bool hasTextures() const;  // diffuse or specular maps, a paint's thickness map included
    bool hasNormalMaps() const;
    bool hasTransparency() const;  // any filter or absorbing medium
    bool hasEmitters() const;      // any material with emitted radiance
    // Whether the response pass carries this scene's transparent objects to the display image: sheets
    // and media (their optical depth per pixel, τ applied band by band inside the response sum), at
    // most 32 materials of them (one channel pass), over surfaces without textures or Donaldson
    // matrices (whose responses are summed per texel, or need the excitation per band), and one slab object
    // if it is planar (crossed once, at one angle: its reflection needs nothing else's in depth
    // order); at most 16 sheet and medium materials beside it (docs/color.md, "The response pass").
    bool transparencyInResponses() const;
    // Whether the display image must come from bands, not the response pass: transparent objects it
    // does not carry (above), interreflection's indirect light and emitted radiance, which only the
    // band programs draw (render/display_frame.cpp).
    bool displayNeedsBands() const {
        return (hasTransparency() && !transparencyInResponses()) || interreflection.has_value() || hasEmitters();
    }
    size_t triangleCount() const;
};

// Meshes as Mesh promises them — a material that exists, one normal, UV and tangent (when
// present) per position, whole triangles, indices in range — else an input error naming the
// object. Both renderers call it before reading the meshes.
void checkMeshes(const Scene& scene);

}  // namespace metamer
