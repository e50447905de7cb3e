// Scene description of the example renderer: triangles with diffuse materials, some emissive,
// and an optional suggested camera. Built in (Cornell box, procedural many lights) or loaded
// from Wavefront OBJ/MTL.
#pragma once

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <restir/core/rng.hpp>

#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace pt {

/// The renderer's random streams (the `stream` of `restir::make_pixel_rng`), numbered after the
/// library's.
struct RenderStream {
    static constexpr std::uint32_t pixel_jitter = restir::RngStream::application;
    static constexpr std::uint32_t independent = pixel_jitter + 1u; ///< uniform, ris, reference
    static constexpr std::uint32_t light_tiles = pixel_jitter + 2u;
    static constexpr std::uint32_t path = pixel_jitter + 3u;         ///< path-traced indirect light
    static constexpr std::uint32_t scene_layout = pixel_jitter + 4u; ///< many-light scene
    static constexpr std::uint32_t grid_jitter = pixel_jitter + 5u;  ///< --source grid lookups
};

/// A diffuse material: reflectance and emitted radiance (both linear RGB).
struct Material {
    std::string name;
    glm::vec3 albedo{0.8f};
    glm::vec3 emission{0.0f};

    bool is_emissive() const { return emission.x > 0.0f || emission.y > 0.0f || emission.z > 0.0f; }
};

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

/// Indexed triangles, one material per triangle. Emissive triangles are one-sided: they emit
/// on the side their geometric normal points to, normal = normalize(cross(b - a, c - a)).
struct Scene {
    std::string name;
    std::vector<glm::vec3> positions;
    std::vector<std::uint32_t> indices; ///< Three per triangle.
    std::vector<std::uint32_t> triangle_materials;
    std::vector<Material> materials;
    std::optional<CameraSetup> camera; ///< Suggested camera; framed from the bounds otherwise.

    std::uint32_t triangle_count() const {
        return static_cast<std::uint32_t>(triangle_materials.size());
    }
};

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

/// A floor lit by `light_count` small emissive quads (two triangles each) floating above it,
/// with colours and intensities drawn from `seed`; for light-count scaling measurements.
/// Throws SceneError for a count of 0 or above 10 million.
Scene make_many_lights(std::uint32_t light_count, std::uint64_t seed);

/// Wavefront OBJ with its MTL files (tinyobjloader): `Kd` is the diffuse albedo, `Ke` the
/// emitted radiance; other MTL properties are ignored. Polygons are triangulated. Throws
/// SceneError with a one-line message for a missing, unreadable or malformed file (numbers
/// that are not finite, indices out of range), or a scene without triangles.
Scene load_obj(const std::filesystem::path& path);

/// The same from text in memory: `mtl_text` is what every `mtllib` of `obj_text` reads, and
/// `name` appears in messages (for tests and fuzzing).
Scene parse_obj(std::string_view obj_text, std::string_view mtl_text, const std::string& name);

/// A bounding box (lower above upper when empty).
struct SceneBounds {
    glm::vec3 lower{std::numeric_limits<float>::max()};
    glm::vec3 upper{std::numeric_limits<float>::lowest()};
};

/// The scene's bounding box (empty when it has no vertices).
SceneBounds bounds_of(const Scene& scene);

/// Length of the diagonal of the scene's bounding box (at least 1e-6): the scale of ray
/// offsets and default radii.
float scene_size(const Scene& scene);

/// A camera that looks at the scene's bounding box from the front (+z), for scenes without
/// one: the box's front face fills an image of aspect ratio `aspect` (width / height).
CameraSetup frame_bounds(const Scene& scene, float aspect);

} // namespace pt
