// Light shapes: the scene's primitives besides its triangles (spheres), each one struct that
// knows its geometry, its points and its emission bounds. The scene keeps one list per shape
// type (`Shapes`); the emitters (lights.hpp), the Embree adapter (embree_scene.cpp) and the
// scene's bounds dispatch over them, so that a new shape is its header and one entry in
// `Shapes` (docs/renderer.md, "Adding a light shape").
#pragma once

#include "shape_sphere.hpp"

#include <restir/light/light_bounds.hpp>
#include <restir/light/solid_angle.hpp>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <concepts>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <tuple>
#include <vector>

namespace pt {

/// What the renderer asks of a light shape (Sphere, shape_sphere.hpp, is the example).
/// Geometry: its box (`lower`, `upper`), the nearest t in (t_min, t_max) at which a ray
/// origin + t direction meets it (infinity where it misses; the direction need not be unit)
/// and the unit normal at a point of it, towards the side it emits from. Points: its `area`, a
/// point uniform by area from uv in [0, 1)^2, a point drawn from a receiver `from` with its
/// solid-angle density (restir::SolidAngleSample; pdf 0: none), and that density at a point a
/// ray from `from` found. Emission bounds for the light BVH (restir::LightBounds with a power),
/// `invalid_reason` (null when it can be rendered), its `material` and its `kind` in messages.
template <class S>
concept LightShape = requires(const S& shape, glm::vec3 p, glm::vec2 uv, float t) {
    { S::kind } -> std::convertible_to<std::string_view>;
    { shape.material } -> std::convertible_to<std::uint32_t>;
    { shape.invalid_reason() } -> std::convertible_to<const char*>;
    { shape.lower() } -> std::same_as<glm::vec3>;
    { shape.upper() } -> std::same_as<glm::vec3>;
    { shape.intersect(p, p, t, t) } -> std::same_as<float>;
    { shape.normal_at(p) } -> std::same_as<glm::vec3>;
    { shape.area() } -> std::same_as<float>;
    { shape.sample_area(uv) } -> std::same_as<glm::vec3>;
    { shape.sample_from(p, uv) } -> std::same_as<restir::SolidAngleSample>;
    { shape.pdf_from(p, p) } -> std::same_as<float>;
    { shape.light_bounds(t) } -> std::same_as<restir::LightBounds>;
};

/// One list per shape type, in the order of `Types`. Shape k of the scene is the k-th of their
/// concatenation; its primitive id is the scene's triangle count + k.
template <LightShape... Types>
class ShapeLists {
public:
    /// Appends `shape` to the list of its type.
    template <class S>
    void add(const S& shape) {
        std::get<std::vector<S>>(lists_).push_back(shape);
    }
    /// The shapes of type S.
    template <class S>
    const std::vector<S>& of() const {
        return std::get<std::vector<S>>(lists_);
    }
    /// Shapes of every type.
    std::uint32_t count() const {
        std::size_t total = 0;
        for_each_list([&](const auto& list) { total += list.size(); });
        return static_cast<std::uint32_t>(total);
    }
    /// body(list) for the list of each type, in order.
    template <class Body>
    void for_each_list(Body&& body) const {
        std::apply([&](const auto&... lists) { (body(lists), ...); }, lists_);
    }
    /// body(shape k); body returns the same type for every shape type.
    template <class Body>
    decltype(auto) visit(std::uint32_t k, Body&& body) const {
        return visit_from<0>(k, body);
    }
    /// The material of shape k.
    std::uint32_t material(std::uint32_t k) const {
        return visit(k, [](const auto& shape) { return shape.material; });
    }

private:
    template <std::size_t I, class Body>
    decltype(auto) visit_from(std::uint32_t k, Body& body) const {
        const auto& list = std::get<I>(lists_);
        if constexpr (I + 1 == sizeof...(Types)) {
            return body(list[k]);
        } else {
            if (k < list.size())
                return body(list[k]);
            return visit_from<I + 1>(k - static_cast<std::uint32_t>(list.size()), body);
        }
    }

    std::tuple<std::vector<Types>...> lists_;
};

/// Every light shape the renderer knows, in the order of their primitive ids.
using Shapes = ShapeLists<Sphere>;

} // namespace pt
