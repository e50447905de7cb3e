// Scene description of the example renderer: triangles and light shapes (spheres) with
// materials, some emissive, an optional environment light and an optional suggested camera.
// Built in (Cornell box, the box lit by spheres, procedural many lights, sun and sky) or loaded
// from Wavefront OBJ/MTL.
#pragma once

#include "shapes.hpp"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <restir/bsdf/glossy_bsdf.hpp>
#include <restir/core/rng.hpp>

#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace pt {

struct Environment; // environment.hpp

/// The renderer's random streams (the `stream` of `restir::make_pixel_rng`), numbered after the
/// library's.
struct RenderStream {
    static constexpr std::uint32_t pixel_jitter = restir::RngStream::application;
    static constexpr std::uint32_t independent = pixel_jitter + 1u; ///< uniform, ris, reference
    static constexpr std::uint32_t light_tiles = pixel_jitter + 2u;
    static constexpr std::uint32_t path = pixel_jitter + 3u;         ///< path-traced indirect light
    static constexpr std::uint32_t scene_layout = pixel_jitter + 4u; ///< many-light scene
    static constexpr std::uint32_t grid_jitter = pixel_jitter + 5u;  ///< --source grid lookups
    /// The ReSTIR GI frame's streams (--gi restir-gi): this plus restir::RngStream's, apart
    /// from the ReSTIR DI frame's.
    static constexpr std::uint32_t restir_gi = 128u;
};

/// A material in the metallic-roughness form: a base colour, a dielectric specular lobe of
/// reflectance `specular` at normal incidence, or a metal (`metallic` 1) whose specular
/// colour is the base colour; and emitted radiance. Colours are linear RGB. A default material
/// (specular 0, metallic 0) is Lambertian: albedo / pi.
struct Material {
    std::string name;
    glm::vec3 albedo{0.8f};   ///< The base colour: a dielectric's diffuse albedo, a metal's F0.
    glm::vec3 emission{0.0f}; ///< Emitted radiance (front side only).
    float specular = 0.0f;    ///< Dielectric F0 in [0, 1]: 0 has no specular lobe, 0.04 is common.
    float roughness = 1.0f;   ///< Perceptual roughness in [0, 1] (GGX alpha = roughness^2).
    float metallic = 0.0f;    ///< In [0, 1]: 1 is a metal, between blends the two.

    bool is_emissive() const { return emission.x > 0.0f || emission.y > 0.0f || emission.z > 0.0f; }
    /// True when the material has no specular lobe: albedo / pi, as every material once was.
    bool is_lambertian() const { return specular == 0.0f && metallic == 0.0f; }
    /// The reflection model: GlossyBsdf::from_metallic_roughness(albedo, metallic, roughness,
    /// specular): diffuse albedo = albedo (1 - metallic), F0 = mix(specular, albedo, metallic).
    restir::GlossyBsdf bsdf() const {
        return restir::GlossyBsdf::from_metallic_roughness(albedo, metallic, roughness, specular);
    }
    /// The material without its specular lobe: Lambertian with the base colour as albedo (a
    /// metal becomes diffuse in its colour).
    Material diffuse() const {
        Material lambertian = *this;
        lambertian.specular = 0.0f;
        lambertian.metallic = 0.0f;
        return lambertian;
    }
};

/// Which materials a render uses: the scene's (`mtl`, with their specular lobes), or every one
/// made Lambertian (`diffuse`, Material::diffuse) for comparisons that assume diffuse scenes.
enum class MaterialMode { mtl, diffuse };

/// Where the camera looks from, at, and its vertical field of view.
/// Largest coordinate a scene vertex or the camera may have: Embree takes no ray origin or
/// vertex beyond about 1.8e18, and rays need room around them.
inline constexpr float max_coordinate = 1e15f;

struct CameraSetup {
    glm::vec3 look_from{0.0f, 0.0f, 1.0f};
    glm::vec3 look_at{0.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    float fov_degrees = 40.0f;
};

/// Indexed triangles, one material per triangle, and light shapes (shapes.hpp), one material
/// each. Primitive ids number the triangles first, then the shapes. Emitters are one-sided:
/// a triangle emits on the side its geometric normal points to, normal =
/// normalize(cross(b - a, c - a)); a shape on the side its `normal_at` faces (a sphere's
/// outside).
struct Scene {
    std::string name;
    std::vector<glm::vec3> positions;
    std::vector<std::uint32_t> indices; ///< Three per triangle.
    std::vector<std::uint32_t> triangle_materials;
    Shapes shapes; ///< Primitives triangle_count() and on.
    std::vector<Material> materials;
    std::optional<CameraSetup> camera; ///< Suggested camera; framed from the bounds otherwise.
    /// Radiance arriving from infinitely far away where rays leave the scene (--env, or the
    /// sun-sky scene's sky); null: black.
    std::shared_ptr<const Environment> environment;

    std::uint32_t triangle_count() const {
        return static_cast<std::uint32_t>(triangle_materials.size());
    }
    /// The material of primitive `primitive` (a triangle, or a shape after them).
    std::uint32_t material_of(std::uint32_t primitive) const {
        return primitive < triangle_count() ? triangle_materials[primitive]
                                            : shapes.material(primitive - triangle_count());
    }
};

/// Throws SceneError naming the first shape of `scene` that cannot be rendered: its own
/// `invalid_reason`, a box that is not finite or reaches beyond max_coordinate, or a material
/// index out of range.
void check_shapes(const Scene& scene);

/// Every material of `scene` made Lambertian (Material::diffuse).
void make_materials_diffuse(Scene& scene);

/// Triangle `t` of a scene as its first corner and the edges from there, in winding order.
struct Triangle {
    glm::vec3 a;  ///< The first corner.
    glm::vec3 ab; ///< The second corner minus the first.
    glm::vec3 ac; ///< The third corner minus the first.

    Triangle(const Scene& scene, std::uint32_t t)
        : a(scene.positions[scene.indices[3 * t + 0]]),
          ab(scene.positions[scene.indices[3 * t + 1]] - a),
          ac(scene.positions[scene.indices[3 * t + 2]] - a) {}

    /// cross(ab, ac): along the geometric normal, twice the area long.
    glm::vec3 normal_times_twice_area() const { return glm::cross(ab, ac); }
    /// Twice the area (0 for a degenerate triangle).
    float twice_area() const { return glm::length(normal_times_twice_area()); }
    /// The unit geometric normal, or `degenerate` when the triangle has no area. Out of line,
    /// so that the BVH and the emitters agree on it to the bit.
    glm::vec3 normal(glm::vec3 degenerate = {0.0f, 1.0f, 0.0f}) const;
};

/// A scene that cannot be built or loaded; `what()` is a one-line message for the user.
struct SceneError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// The classic Cornell box with its published measured geometry (millimetres), the usual RGB
/// reflectances and light, and the published camera.
Scene make_cornell_box();

/// The same box with glossy materials ("cornell-glossy"): a polished dielectric floor
/// (roughness 0.12) that mirrors the light and the blocks, a gold-coloured metal tall block
/// (roughness 0.25) and a rough dielectric short block (roughness 0.6); the walls, the ceiling
/// and the light as in make_cornell_box.
Scene make_glossy_cornell_box();

/// The Cornell box without its ceiling light, lit by three small emissive spheres of
/// different colours ("cornell-spheres"): one above the short block, one in front of the tall
/// block, one under the ceiling.
Scene make_cornell_spheres();

/// A floor lit by `light_count` small emissive quads (two triangles each) floating above it,
/// with colours and intensities drawn from `seed`; for light-count scaling measurements.
/// Throws SceneError for a count of 0 or above 10 million.
Scene make_many_lights(std::uint32_t light_count, std::uint64_t seed);

/// An open scene under `environment` ("sun-sky"): a large grey ground, blocks, an arch and a
/// low wall that cast shadows and hide part of the sky, a polished metal block, and two
/// small emissive panels (local lights next to the sky); the camera sees the horizon.
Scene make_sun_sky_scene(std::shared_ptr<const Environment> environment);

/// Wavefront OBJ with its MTL files (tinyobjloader). Materials as Blender's exporter writes
/// them from its Principled BSDF (docs/renderer.md): `Kd` is the base colour, `Ke` the emitted
/// radiance, `Ks` the "specular" input (F0 = 0.08 Ks, its mean over the channels, at most
/// 0.08), `Pr` the roughness, or without it 1 - sqrt(Ns) / 30 (`Ns` = ((1 - roughness) 30)^2),
/// `Pm` the metallic; other MTL properties are ignored. Polygons are triangulated. Throws
/// SceneError with a one-line message for a missing, unreadable or malformed file (numbers
/// that are not finite, negative material values, indices out of range), or a scene without
/// triangles.
Scene load_obj(const std::filesystem::path& path);

/// The same from text in memory: `mtl_text` is what every `mtllib` of `obj_text` reads, and
/// `name` appears in messages (for tests and fuzzing).
Scene parse_obj(std::string_view obj_text, std::string_view mtl_text, const std::string& name);

/// A bounding box (lower above upper when empty).
struct SceneBounds {
    glm::vec3 lower{std::numeric_limits<float>::max()};
    glm::vec3 upper{std::numeric_limits<float>::lowest()};
};

/// The scene's bounding box, its shapes' boxes included (empty when it has no vertices and no
/// shapes).
SceneBounds bounds_of(const Scene& scene);

/// Length of the diagonal of the scene's bounding box (at least 1e-6): the scale of ray
/// offsets and default radii.
float scene_size(const Scene& scene);

/// A camera that looks at the scene's bounding box from the front (+z), for scenes without
/// one: the box's front face fills an image of aspect ratio `aspect` (width / height).
CameraSetup frame_bounds(const Scene& scene, float aspect);

} // namespace pt
