// Recording the rays a photon pass casts, and casting them again bare: the two halves of the
// "shooting vs the same rays bare" comparison in bm_vpl.cpp and bm_photons_embree.cpp.
#pragma once

#include <benchmark/benchmark.h>
#include <glm/vec3.hpp>

#include <vector>

namespace bench {

struct Ray {
    glm::vec3 origin{0.0f};
    glm::vec3 direction{0.0f};
};

/// A ClosestHitQuery that appends every ray it is asked to cast to `rays`, then casts it with
/// `query`.
template <class Query>
struct RecordingQuery {
    const Query* query = nullptr;
    std::vector<Ray>* rays = nullptr;

    auto closest_hit(glm::vec3 origin, glm::vec3 direction) const {
        rays->push_back({origin, direction});
        return query->closest_hit(origin, direction);
    }
};

/// Casts `rays` through `query` with nothing around them (the hit positions are summed so that
/// the compiler keeps the casts).
template <class Query>
void cast_bare(const Query& query, const std::vector<Ray>& rays) {
    glm::vec3 sum{0.0f};
    for (const Ray& ray : rays) {
        const auto hit = query.closest_hit(ray.origin, ray.direction);
        if (is_valid_surface(hit))
            sum += surface_position(hit);
    }
    benchmark::DoNotOptimize(sum);
}

} // namespace bench
