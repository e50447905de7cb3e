#include "embree_scene.hpp"

#include <embree3/rtcore.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>

namespace pt {

namespace {

void report_error(void* /*user*/, RTCError code, const char* message) {
    (void)code;
    (void)message; // surfaced through rtcGetDeviceError after each call that matters
}

// A list of light shapes as Embree user geometry: its boxes and its ray intersections are the
// shapes' own (LightShape), for single rays and packets alike. The hit's normal is left to the
// adapter (EmbreeScene::complete_hit), as for triangles.
template <class Shape>
struct ShapeGeometry {
    static const Shape& shape_of(void* user, unsigned primitive) {
        return static_cast<const Shape*>(user)[primitive];
    }
    static void bounds(const RTCBoundsFunctionArguments* args) {
        const Shape& shape = shape_of(args->geometryUserPtr, args->primID);
        const glm::vec3 lower = shape.lower(), upper = shape.upper();
        RTCBounds& box = *args->bounds_o;
        box.lower_x = lower.x;
        box.lower_y = lower.y;
        box.lower_z = lower.z;
        box.upper_x = upper.x;
        box.upper_y = upper.y;
        box.upper_z = upper.z;
    }
    // Where ray i of the N of `rays` meets `shape` inside its (tnear, tfar), or infinity.
    static float distance(const Shape& shape, RTCRayN* rays, unsigned n, unsigned i) {
        const glm::vec3 origin{RTCRayN_org_x(rays, n, i), RTCRayN_org_y(rays, n, i),
                               RTCRayN_org_z(rays, n, i)};
        const glm::vec3 direction{RTCRayN_dir_x(rays, n, i), RTCRayN_dir_y(rays, n, i),
                                  RTCRayN_dir_z(rays, n, i)};
        return shape.intersect(origin, direction, RTCRayN_tnear(rays, n, i),
                               RTCRayN_tfar(rays, n, i));
    }
    static void intersect(const RTCIntersectFunctionNArguments* args) {
        const Shape& shape = shape_of(args->geometryUserPtr, args->primID);
        RTCRayN* rays = RTCRayHitN_RayN(args->rayhit, args->N);
        RTCHitN* hits = RTCRayHitN_HitN(args->rayhit, args->N);
        for (unsigned i = 0; i < args->N; ++i) {
            const float t = args->valid[i] == 0 ? std::numeric_limits<float>::infinity()
                                                : distance(shape, rays, args->N, i);
            if (!(t < std::numeric_limits<float>::infinity()))
                continue;
            RTCRayN_tfar(rays, args->N, i) = t;
            RTCHitN_Ng_x(hits, args->N, i) = 0.0f;
            RTCHitN_Ng_y(hits, args->N, i) = 0.0f;
            RTCHitN_Ng_z(hits, args->N, i) = 0.0f;
            RTCHitN_u(hits, args->N, i) = 0.0f;
            RTCHitN_v(hits, args->N, i) = 0.0f;
            RTCHitN_primID(hits, args->N, i) = args->primID;
            RTCHitN_geomID(hits, args->N, i) = args->geomID;
            RTCHitN_instID(hits, args->N, i, 0) = args->context->instID[0];
        }
    }
    static void occluded(const RTCOccludedFunctionNArguments* args) {
        const Shape& shape = shape_of(args->geometryUserPtr, args->primID);
        for (unsigned i = 0; i < args->N; ++i)
            if (args->valid[i] != 0 &&
                distance(shape, args->ray, args->N, i) < std::numeric_limits<float>::infinity())
                RTCRayN_tfar(args->ray, args->N, i) = -std::numeric_limits<float>::infinity();
    }
};

} // namespace

EmbreeScene::EmbreeScene(const Scene& scene) : shapes_(scene.shapes) {
    check_shapes(scene);
    device_ = rtcNewDevice("verbose=0");
    if (device_ == nullptr)
        throw SceneError("Embree: cannot create a device");
    rtcSetDeviceErrorFunction(device_, report_error, nullptr);
    scene_ = rtcNewScene(device_);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
    if (scene.triangle_count() > 0u || shapes_.count() == 0u)
        attach_triangles(scene);
    attach_shapes();
    rtcCommitScene(scene_);
    if (const RTCError error = rtcGetDeviceError(device_); error != RTC_ERROR_NONE)
        throw SceneError("Embree: building the scene failed (error " +
                         std::to_string(static_cast<int>(error)) + ")");
}

// The triangles as Embree geometry 0, with their normals.
void EmbreeScene::attach_triangles(const Scene& scene) {
    RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                3 * sizeof(float), scene.positions.size()));
    auto* indices = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                3 * sizeof(unsigned), scene.triangle_count()));
    if (vertices == nullptr || indices == nullptr) {
        rtcReleaseGeometry(geometry);
        throw SceneError("Embree: cannot allocate the geometry buffers");
    }
    for (std::size_t i = 0; i < scene.positions.size(); ++i) {
        vertices[3 * i + 0] = scene.positions[i].x;
        vertices[3 * i + 1] = scene.positions[i].y;
        vertices[3 * i + 2] = scene.positions[i].z;
    }
    std::memcpy(indices, scene.indices.data(), scene.indices.size() * sizeof(unsigned));
    normals_.resize(scene.triangle_count());
    for (std::uint32_t t = 0; t < scene.triangle_count(); ++t)
        normals_[t] = Triangle(scene, t).normal();
    rtcCommitGeometry(geometry);
    first_primitive_.resize(rtcAttachGeometry(scene_, geometry) + 1u, 0u);
    rtcReleaseGeometry(geometry);
}

// Each non-empty list of shapes as one Embree user geometry (ShapeGeometry), their primitive
// ids after the triangles' in the order of Scene::shapes.
void EmbreeScene::attach_shapes() {
    auto first = static_cast<std::uint32_t>(normals_.size());
    shapes_.for_each_list([&](const auto& list) {
        using Shape = typename std::decay_t<decltype(list)>::value_type;
        if (!list.empty()) {
            RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_USER);
            rtcSetGeometryUserPrimitiveCount(geometry, static_cast<unsigned>(list.size()));
            rtcSetGeometryUserData(geometry, const_cast<Shape*>(list.data()));
            rtcSetGeometryBoundsFunction(geometry, &ShapeGeometry<Shape>::bounds, nullptr);
            rtcSetGeometryIntersectFunction(geometry, &ShapeGeometry<Shape>::intersect);
            rtcSetGeometryOccludedFunction(geometry, &ShapeGeometry<Shape>::occluded);
            rtcCommitGeometry(geometry);
            const unsigned id = rtcAttachGeometry(scene_, geometry);
            rtcReleaseGeometry(geometry);
            first_primitive_.resize(std::max<std::size_t>(first_primitive_.size(), id + 1u), 0u);
            first_primitive_[id] = first;
        }
        first += static_cast<std::uint32_t>(list.size());
    });
}

void EmbreeScene::complete_hit(Hit& hit, unsigned geometry, unsigned primitive, glm::vec3 origin,
                               glm::vec3 direction, float t) const {
    hit.found = true;
    hit.primitive = first_primitive_[geometry] + primitive;
    hit.distance = t * glm::length(direction);
    hit.position = origin + t * direction;
    const auto triangles = static_cast<std::uint32_t>(normals_.size());
    hit.normal = hit.primitive < triangles
                     ? normals_[hit.primitive]
                     : shapes_.visit(hit.primitive - triangles, [&](const auto& shape) {
                           return shape.normal_at(hit.position);
                       });
}

EmbreeScene::~EmbreeScene() {
    if (scene_ != nullptr)
        rtcReleaseScene(scene_);
    if (device_ != nullptr)
        rtcReleaseDevice(device_);
}

Hit EmbreeScene::closest_hit(glm::vec3 origin, glm::vec3 direction) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit query{};
    query.ray.org_x = origin.x;
    query.ray.org_y = origin.y;
    query.ray.org_z = origin.z;
    query.ray.dir_x = direction.x;
    query.ray.dir_y = direction.y;
    query.ray.dir_z = direction.z;
    query.ray.tnear = 0.0f;
    query.ray.tfar = std::numeric_limits<float>::infinity();
    query.ray.mask = 0xffffffffu;
    query.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    query.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_, &context, &query);
    Hit hit;
    if (query.hit.geomID != RTC_INVALID_GEOMETRY_ID)
        complete_hit(hit, query.hit.geomID, query.hit.primID, origin, direction, query.ray.tfar);
    return hit;
}

bool EmbreeScene::occluded(glm::vec3 from, glm::vec3 to) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay ray{};
    ray.org_x = from.x;
    ray.org_y = from.y;
    ray.org_z = from.z;
    const glm::vec3 d = to - from;
    ray.dir_x = d.x;
    ray.dir_y = d.y;
    ray.dir_z = d.z;
    ray.tnear = 0.0f;
    ray.tfar = 1.0f;
    ray.mask = 0xffffffffu;
    rtcOccluded1(scene_, &context, &ray);
    return ray.tfar < 0.0f; // Embree sets tfar to -inf on a hit
}

// Batches go through Embree's 16-wide packets (rtcIntersect16 / rtcOccluded16, native on
// AVX-512), primary rays with the coherent context flag, shadow rays with the default
// (incoherent) one. Measured on the Cornell box, one thread, 64 rays per call (8 x 8 pixel
// blocks, benchmarks/bm_rays_embree.cpp), in rays/s against rtcIntersect1 / rtcOccluded1:
// primary 16-wide 4.7x, 8-wide 4.0x, rtcIntersect1M 3.9x (all coherent; 16-wide without the
// flag only 1.9x); shadow 16-wide 3.6x (coherent flag 2.8x), 8-wide 2.2x, rtcOccluded1M 2.2x.
namespace {
constexpr std::size_t packet = 16;
}

void EmbreeScene::closest_hits(glm::vec3 origin, std::span<const glm::vec3> directions,
                               std::span<Hit> hits) const {
    assert(directions.size() == hits.size());
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    alignas(64) int valid[packet];
    RTCRayHit16 query{}; // lanes past the tail keep earlier (finite) values and are masked off
    for (std::size_t begin = 0; begin < directions.size(); begin += packet) {
        const std::size_t count = std::min(packet, directions.size() - begin);
        for (std::size_t i = 0; i < packet; ++i) {
            valid[i] = i < count ? -1 : 0;
            if (i >= count)
                continue;
            const glm::vec3 d = directions[begin + i];
            query.ray.org_x[i] = origin.x;
            query.ray.org_y[i] = origin.y;
            query.ray.org_z[i] = origin.z;
            query.ray.dir_x[i] = d.x;
            query.ray.dir_y[i] = d.y;
            query.ray.dir_z[i] = d.z;
            query.ray.tnear[i] = 0.0f;
            query.ray.tfar[i] = std::numeric_limits<float>::infinity();
            query.ray.mask[i] = 0xffffffffu;
            query.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
            query.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
        }
        rtcIntersect16(valid, scene_, &context, &query);
        for (std::size_t i = 0; i < count; ++i) {
            Hit& hit = hits[begin + i];
            hit = Hit{};
            if (query.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID)
                continue;
            complete_hit(hit, query.hit.geomID[i], query.hit.primID[i], origin,
                         directions[begin + i], query.ray.tfar[i]);
        }
    }
}

void EmbreeScene::occluded_segments(std::span<const glm::vec3> from, std::span<const glm::vec3> to,
                                    std::span<std::uint8_t> blocked) const {
    assert(from.size() == to.size() && from.size() == blocked.size());
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    alignas(64) int valid[packet];
    RTCRay16 ray{};
    for (std::size_t begin = 0; begin < from.size(); begin += packet) {
        const std::size_t count = std::min(packet, from.size() - begin);
        for (std::size_t i = 0; i < packet; ++i) {
            valid[i] = i < count ? -1 : 0;
            if (i >= count)
                continue;
            const glm::vec3 o = from[begin + i];
            const glm::vec3 d = to[begin + i] - o;
            ray.org_x[i] = o.x;
            ray.org_y[i] = o.y;
            ray.org_z[i] = o.z;
            ray.dir_x[i] = d.x;
            ray.dir_y[i] = d.y;
            ray.dir_z[i] = d.z;
            ray.tnear[i] = 0.0f;
            ray.tfar[i] = 1.0f;
            ray.mask[i] = 0xffffffffu;
        }
        rtcOccluded16(valid, scene_, &context, &ray);
        for (std::size_t i = 0; i < count; ++i)
            blocked[begin + i] = ray.tfar[i] < 0.0f ? 1u : 0u;
    }
}

} // namespace pt
