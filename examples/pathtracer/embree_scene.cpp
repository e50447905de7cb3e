#include "embree_scene.hpp"

#include <embree3/rtcore.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>

namespace pt {

namespace {

void report_error(void* /*user*/, RTCError code, const char* message) {
    (void)code;
    (void)message; // surfaced through rtcGetDeviceError after each call that matters
}

} // namespace

EmbreeScene::EmbreeScene(const Scene& scene) {
    device_ = rtcNewDevice("verbose=0");
    if (device_ == nullptr)
        throw SceneError("Embree: cannot create a device");
    rtcSetDeviceErrorFunction(device_, report_error, nullptr);
    scene_ = rtcNewScene(device_);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);

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
    for (std::uint32_t t = 0; t < scene.triangle_count(); ++t) {
        const glm::vec3 a = scene.positions[scene.indices[3 * t + 0]];
        const glm::vec3 b = scene.positions[scene.indices[3 * t + 1]];
        const glm::vec3 c = scene.positions[scene.indices[3 * t + 2]];
        const glm::vec3 n = glm::cross(b - a, c - a);
        const float length = glm::length(n);
        normals_[t] = length > 0.0f ? n / length : glm::vec3(0.0f, 1.0f, 0.0f);
    }
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene_, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(scene_);
    if (const RTCError error = rtcGetDeviceError(device_); error != RTC_ERROR_NONE)
        throw SceneError("Embree: building the scene failed (error " +
                         std::to_string(static_cast<int>(error)) + ")");
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
    if (query.hit.geomID == RTC_INVALID_GEOMETRY_ID)
        return hit;
    hit.found = true;
    hit.triangle = query.hit.primID;
    hit.distance = query.ray.tfar * glm::length(direction);
    hit.position = origin + query.ray.tfar * direction;
    hit.normal = normals_[hit.triangle];
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

} // namespace pt
