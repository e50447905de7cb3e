// Wavefront OBJ/MTL scenes: the text checked, then read with tinyobjloader into a Scene.
#include "scene.hpp"

#include "messages.hpp"

#include <glm/common.hpp>
#include <glm/vec3.hpp>

#include <tiny_obj_loader.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

namespace pt {

namespace {

// ---- Checks of OBJ and MTL text before tinyobjloader reads it: it reads a number it cannot
// parse ("nan", "1e400", "x") as 0 and lets face indices overflow an int. ----

using Fail = std::function<SceneError(std::string_view)>;

// The whitespace-separated tokens of one line, up to a '#' comment.
std::vector<std::string_view> tokens_of(std::string_view line) {
    std::vector<std::string_view> tokens;
    std::size_t at = 0;
    while (at < line.size()) {
        while (at < line.size() && (line[at] == ' ' || line[at] == '\t' || line[at] == '\r'))
            ++at;
        if (at >= line.size() || line[at] == '#')
            break;
        const std::size_t begin = at;
        while (at < line.size() && line[at] != ' ' && line[at] != '\t' && line[at] != '\r')
            ++at;
        tokens.push_back(line.substr(begin, at - begin));
    }
    return tokens;
}

// A token as it appears in a message: printable and short.
std::string shown(std::string_view token) {
    std::string text;
    for (char c : token.substr(0, 24))
        text += std::isprint(static_cast<unsigned char>(c)) != 0 ? c : '?';
    return token.size() > 24 ? text + "..." : text;
}

bool is_finite_number(std::string_view token) {
    if (!token.empty() && token.front() == '+')
        token.remove_prefix(1);
    double value = 0.0;
    const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
    return error == std::errc() && end == token.data() + token.size() && std::isfinite(value);
}

// Calls `check(line_number, tokens)` for every line of `text` that has tokens.
template <class Check>
void for_each_line(std::string_view text, Check check) {
    std::size_t number = 0;
    while (!text.empty()) {
        ++number;
        const std::size_t end = text.find('\n');
        const std::vector<std::string_view> tokens = tokens_of(text.substr(0, end));
        text = end == std::string_view::npos ? std::string_view{} : text.substr(end + 1);
        if (!tokens.empty())
            check(number, tokens);
    }
}

void check_numbers(std::size_t line, const std::vector<std::string_view>& tokens, std::size_t first,
                   const Fail& fail) {
    for (std::size_t i = first; i < tokens.size(); ++i)
        if (!is_finite_number(tokens[i]))
            throw fail("line " + std::to_string(line) + ": '" + shown(tokens[i]) +
                       "' is not a finite number");
}

void check_obj_text(std::string_view text, const Fail& fail) {
    for_each_line(text, [&](std::size_t line, const std::vector<std::string_view>& tokens) {
        const std::string_view keyword = tokens.front();
        if (keyword == "v" || keyword == "vn" || keyword == "vt") {
            if (keyword == "v" && tokens.size() < 4)
                throw fail("line " + std::to_string(line) + ": a vertex needs three coordinates");
            check_numbers(line, tokens, 1, fail);
        } else if (keyword == "f" || keyword == "l" || keyword == "p") {
            for (std::size_t i = 1; i < tokens.size(); ++i) {
                std::string_view rest = tokens[i];
                while (true) { // v, v/vt, v//vn, v/vt/vn: each present index a non-zero int
                    const std::size_t slash = rest.find('/');
                    const std::string_view part = rest.substr(0, slash);
                    std::int64_t index = 0;
                    const auto [end, error] =
                        std::from_chars(part.data(), part.data() + part.size(), index);
                    const bool empty_allowed = part.empty() && part.data() != tokens[i].data();
                    if (!empty_allowed &&
                        (error != std::errc() || end != part.data() + part.size() || index == 0 ||
                         index > std::numeric_limits<std::int32_t>::max() ||
                         index < -std::numeric_limits<std::int32_t>::max()))
                        throw fail("line " + std::to_string(line) + ": bad index '" +
                                   shown(tokens[i]) + "'");
                    if (slash == std::string_view::npos)
                        break;
                    rest = rest.substr(slash + 1);
                }
            }
        }
    });
}

// After check_numbers: the numbers from `first` on are at least 0 (-0 included).
void check_not_negative(std::size_t line, const std::vector<std::string_view>& tokens,
                        std::size_t first, const Fail& fail) {
    for (std::size_t i = first; i < tokens.size(); ++i) {
        double value = 0.0;
        std::from_chars(tokens[i].data(), tokens[i].data() + tokens[i].size(), value);
        if (value < 0.0)
            throw fail("line " + std::to_string(line) + ": " + std::string(tokens.front()) + " '" +
                       shown(tokens[i]) + "' is negative");
    }
}

// Values the loader uses must be numbers: "Kd nan" would silently be black. The specular ones
// (Ks, Ns, Pr, Pm) must not be negative either: none of them has a meaning below 0, and -1
// marks an absent Ns or Pr (mark_absent_values).
void check_mtl_text(std::string_view text, const Fail& fail) {
    for_each_line(text, [&](std::size_t line, const std::vector<std::string_view>& tokens) {
        const std::string_view keyword = tokens.front();
        if (keyword == "Kd" || keyword == "Ke" || keyword == "Ka" || keyword == "Ks") {
            if (tokens.size() > 1 && tokens[1] == "spectral")
                return;
            const std::size_t first = tokens.size() > 1 && tokens[1] == "xyz" ? 2 : 1;
            check_numbers(line, tokens, first, fail);
            if (keyword == "Ks")
                check_not_negative(line, tokens, first, fail);
        } else if (keyword == "Ns" || keyword == "Pr" || keyword == "Pm") {
            if (tokens.size() < 2) // tinyobjloader would read 0: a mirror for "Pr"
                throw fail("line " + std::to_string(line) + ": " + std::string(keyword) +
                           " needs a number");
            check_numbers(line, tokens, 1, fail);
            check_not_negative(line, tokens, 1, fail);
        }
    });
}

// tinyobjloader gives no sign of whether a material had Ns or Pr, and its defaults for them
// (Ns 1, Pr 0) are values a file may hold: `text` with "Ns -1" and "Pr -1" after every line
// that starts a material (as tinyobjloader sees one), so that an absent value reads -1, which
// no checked file holds (check_mtl_text).
std::string mark_absent_values(std::string_view text) {
    std::string marked;
    marked.reserve(text.size());
    while (!text.empty()) {
        const std::size_t end = text.find('\n');
        const std::string_view line = text.substr(0, end);
        text = end == std::string_view::npos ? std::string_view{} : text.substr(end + 1);
        marked.append(line).append("\n");
        const std::string_view start =
            line.substr(std::min(line.find_first_not_of(" \t"), line.size()));
        if (start.size() > 6 && start.starts_with("newmtl") &&
            (start[6] == ' ' || start[6] == '\t'))
            marked.append("Ns -1\nPr -1\n");
    }
    return marked;
}

std::string read_text(const std::filesystem::path& path, const std::string& what,
                      const Fail& fail) {
    std::error_code error;
    const std::filesystem::file_status status = std::filesystem::status(path, error);
    if (status.type() == std::filesystem::file_type::not_found)
        throw fail(what + "no such file");
    if (error)
        throw fail(what + error.message());
    if (std::filesystem::is_directory(status))
        throw fail(what + "it is a directory");
    errno = 0;
    std::ifstream in(path, std::ios::binary);
    if (!in)
        throw fail(what + "the file cannot be opened (" + std::generic_category().message(errno) +
                   ")");
    std::stringstream text;
    text << in.rdbuf();
    if (in.bad())
        throw fail(what + "the file cannot be read");
    return text.str();
}

// The material libraries an OBJ text names, in order.
std::vector<std::string> material_libraries(std::string_view text) {
    std::vector<std::string> names;
    for_each_line(text, [&](std::size_t, const std::vector<std::string_view>& tokens) {
        if (tokens.front() == "mtllib")
            for (std::size_t i = 1; i < tokens.size(); ++i)
                names.emplace_back(tokens[i]);
    });
    return names;
}

// What tinyobjloader reads from an OBJ text.
struct ObjData {
    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
    std::vector<tinyobj::material_t> materials;
};

// Material libraries served from text already read and checked, so that no file is read
// twice: `texts` by name, or `fallback` for every name (parse_obj).
class MaterialTexts final : public tinyobj::MaterialReader {
public:
    std::map<std::string, std::string> texts;
    std::optional<std::string> fallback;

    bool operator()(const std::string& name, std::vector<tinyobj::material_t>* materials,
                    std::map<std::string, int>* names, std::string* warning,
                    std::string* error) override {
        const auto found = texts.find(name);
        if (found == texts.end() && !fallback)
            return false; // load_obj checked every library exists before parsing
        std::istringstream in(mark_absent_values(found != texts.end() ? found->second : *fallback));
        tinyobj::LoadMtl(names, materials, &in, warning, error);
        return true;
    }
};

// Blender's Principled BSDF "Specular" input s means F0 = 0.08 s (s = 0.5: 4 %, a refractive
// index of 1.5), and its OBJ exporter writes Ns = ((1 - roughness) 30)^2 (docs/renderer.md).
constexpr float specular_to_f0 = 0.08f;
constexpr float ns_root_scale = 30.0f;

// The renderer's material of an MTL material (checked: no value is negative or not finite,
// and Ns or Pr is -1 when absent, mark_absent_values): Kd the base colour, clamped to [0, 1];
// Ke the emission; F0 = 0.08 Ks (the channels' mean, at most 1: F0 at most 8 %); the
// roughness Pr, or 1 - sqrt(Ns) / 30, or 1 without either; the metallic Pm (both clamped to
// [0, 1]).
Material material_of(const tinyobj::material_t& source) {
    Material material;
    material.name = source.name;
    material.albedo =
        glm::clamp(glm::vec3{source.diffuse[0], source.diffuse[1], source.diffuse[2]}, 0.0f, 1.0f);
    material.emission =
        glm::max(glm::vec3{source.emission[0], source.emission[1], source.emission[2]}, 0.0f);
    const float ks = (source.specular[0] + source.specular[1] + source.specular[2]) / 3.0f;
    material.specular = specular_to_f0 * std::clamp(ks, 0.0f, 1.0f);
    if (source.roughness >= 0.0f)
        material.roughness = std::min(source.roughness, 1.0f);
    else if (source.shininess >= 0.0f)
        material.roughness =
            std::clamp(1.0f - std::sqrt(source.shininess) / ns_root_scale, 0.0f, 1.0f);
    material.metallic = std::clamp(source.metallic, 0.0f, 1.0f);
    return material;
}

// The scene's materials from the OBJ's (material_of), and a "default" one (Lambertian), added
// the first time a face names no material or one that does not exist.
class ObjMaterials {
public:
    ObjMaterials(Scene& scene, const std::vector<tinyobj::material_t>& materials)
        : scene_(scene), obj_count_(static_cast<int>(materials.size())) {
        for (const tinyobj::material_t& source : materials)
            scene_.materials.push_back(material_of(source));
    }

    // The scene material of a face's material id.
    std::uint32_t index(int id) {
        if (id >= 0 && id < obj_count_) {
            return static_cast<std::uint32_t>(id);
        }
        if (default_ == none) {
            default_ = static_cast<std::uint32_t>(scene_.materials.size());
            scene_.materials.push_back({.name = "default"});
        }
        return default_;
    }

private:
    static constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();
    Scene& scene_;
    int obj_count_;
    std::uint32_t default_ = none; // the "default" material, once added
};

// The OBJ's vertices that faces use, appended to the scene's positions when first used, each
// checked: defined, finite and within max_coordinate of the origin.
class ObjVertices {
public:
    ObjVertices(Scene& scene, const std::vector<tinyobj::real_t>& coordinates, const Fail& fail)
        : scene_(scene), coordinates_(coordinates), fail_(fail),
          remap_(coordinates.size() / 3, unused) {}

    // The scene vertex of a face corner.
    std::uint32_t index(const tinyobj::index_t& corner) {
        if (corner.vertex_index < 0 ||
            static_cast<std::size_t>(corner.vertex_index) >= remap_.size()) {
            throw fail_("a face refers to vertex " + std::to_string(corner.vertex_index + 1) +
                        " but the file defines " + std::to_string(remap_.size()) + " vertices");
        }
        const auto source = static_cast<std::size_t>(corner.vertex_index);
        std::uint32_t& target = remap_[source];
        if (target == unused) {
            const glm::vec3 position{coordinates_[3 * source], coordinates_[3 * source + 1],
                                     coordinates_[3 * source + 2]};
            check(position, source);
            target = static_cast<std::uint32_t>(scene_.positions.size());
            scene_.positions.push_back(position);
        }
        return target;
    }

private:
    static constexpr std::uint32_t unused = std::numeric_limits<std::uint32_t>::max();

    void check(glm::vec3 position, std::size_t source) const {
        if (!std::isfinite(position.x) || !std::isfinite(position.y) ||
            !std::isfinite(position.z)) {
            throw fail_("vertex " + std::to_string(source + 1) + " is not finite");
        }
        if (std::abs(position.x) > max_coordinate || std::abs(position.y) > max_coordinate ||
            std::abs(position.z) > max_coordinate) {
            throw fail_("vertex " + std::to_string(source + 1) + " lies beyond 1e15 of the origin");
        }
        if (scene_.positions.size() >= unused) {
            throw fail_("too many vertices");
        }
    }

    Scene& scene_;
    const std::vector<tinyobj::real_t>& coordinates_;
    const Fail& fail_;
    std::vector<std::uint32_t> remap_;
};

// The faces of one OBJ shape as triangle fans.
void add_obj_faces(Scene& scene, const tinyobj::shape_t& shape, ObjMaterials& materials,
                   ObjVertices& vertices, const Fail& fail) {
    const tinyobj::mesh_t& mesh = shape.mesh;
    std::size_t offset = 0;
    for (std::size_t face = 0; face < mesh.num_face_vertices.size(); ++face) {
        const std::size_t corners = mesh.num_face_vertices[face];
        if (offset + corners > mesh.indices.size()) {
            throw fail("inconsistent face data in shape " + shape.name);
        }
        const std::uint32_t material =
            materials.index(face < mesh.material_ids.size() ? mesh.material_ids[face] : -1);
        for (std::size_t k = 1; k + 1 < corners; ++k) {
            scene.indices.push_back(vertices.index(mesh.indices[offset]));
            scene.indices.push_back(vertices.index(mesh.indices[offset + k]));
            scene.indices.push_back(vertices.index(mesh.indices[offset + k + 1]));
            if (scene.triangle_materials.size() >= std::numeric_limits<std::uint32_t>::max()) {
                throw fail("too many triangles");
            }
            scene.triangle_materials.push_back(material);
        }
        offset += corners;
    }
}

// The scene of the data tinyobjloader read: materials, then the triangles with their used
// vertices.
Scene build_scene(const ObjData& data, const std::string& name, const Fail& fail) {
    Scene scene;
    scene.name = name;
    ObjMaterials materials(scene, data.materials);
    ObjVertices vertices(scene, data.attrib.vertices, fail);
    for (const tinyobj::shape_t& shape : data.shapes)
        add_obj_faces(scene, shape, materials, vertices, fail);
    if (scene.triangle_materials.empty()) {
        throw fail("it contains no triangles");
    }
    return scene;
}

// The scene tinyobjloader reads from `obj_text` (checked here) and `libraries` (checked by the
// caller): materials, then the triangles with their used vertices.
Scene read_obj(std::string_view obj_text, MaterialTexts& libraries, const std::string& name,
               const Fail& fail) {
    check_obj_text(obj_text, fail);
    ObjData data;
    std::string warning, error;
    std::istringstream in{std::string(obj_text)};
    if (!tinyobj::LoadObj(&data.attrib, &data.shapes, &data.materials, &warning, &error, &in,
                          &libraries, /*triangulate=*/true, /*default_vcols_fallback=*/false))
        throw fail(error.empty() ? std::string_view{"parse error"} : error);
    return build_scene(data, name, fail);
}

} // namespace

Scene parse_obj(std::string_view obj_text, std::string_view mtl_text, const std::string& name) {
    const Fail fail = [&name](std::string_view reason) {
        return SceneError("cannot read scene " + name + ": " + one_line(reason));
    };
    check_mtl_text(mtl_text, fail);
    MaterialTexts libraries;
    libraries.fallback = std::string(mtl_text);
    return read_obj(obj_text, libraries, name, fail);
}

Scene load_obj(const std::filesystem::path& path) {
    const std::string file = path.string();
    const Fail fail = [&file](std::string_view reason) {
        return SceneError("cannot read scene " + file + ": " + one_line(reason));
    };
    const std::string text = read_text(path, "", fail);
    const std::filesystem::path directory = path.has_parent_path() ? path.parent_path() : ".";
    MaterialTexts libraries;
    for (const std::string& library : material_libraries(text)) {
        const std::filesystem::path mtl = directory / library;
        std::error_code error;
        if (!std::filesystem::exists(mtl, error))
            throw fail("material library " + library + " not found in " + directory.string());
        std::string mtl_text = read_text(mtl, "material library " + library + ": ", fail);
        check_mtl_text(mtl_text, fail);
        libraries.texts.emplace(library, std::move(mtl_text));
    }
    return read_obj(text, libraries, path.stem().string(), fail);
}

} // namespace pt
