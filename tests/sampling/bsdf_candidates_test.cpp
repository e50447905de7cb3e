// Multi-strategy RIS over light and BSDF candidates: unbiased for area lights reached by both
// strategies and for point lights that only light candidates reach, at diffuse and glossy
// receivers, with light candidates drawn per receiver or taken from a light tile; the truth by
// quadrature over the light.
#include <restir/bsdf/glossy_receiver.hpp>
#include <restir/restir.hpp>

#include "support/quadrature.hpp"
#include "support/statistics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace {

using restir::test::RunningStats;

// A rectangular emitter facing down (id 0) and an isotropic point light (id 1).
struct TwoLights {
    glm::vec3 corner{-0.5f, 1.0f, -0.5f};
    glm::vec3 edge0{1.0f, 0.0f, 0.0f};
    glm::vec3 edge1{0.0f, 0.0f, 1.0f};
    glm::vec3 radiance{2.0f, 1.0f, 0.5f};
    glm::vec3 point{0.8f, 0.6f, 0.3f};
    glm::vec3 intensity{0.3f, 0.6f, 0.2f};

    glm::vec3 normal() const { return glm::normalize(glm::cross(edge0, edge1)); } // down
    float area() const { return glm::length(glm::cross(edge0, edge1)); }
    std::uint32_t light_count() const { return 2u; }
    restir::LightSample sample_point(std::uint32_t id, glm::vec2 uv) const {
        restir::LightSample p;
        if (id == 0u) {
            p.position = corner + uv.x * edge0 + uv.y * edge1;
            p.normal = normal();
            p.radiance = radiance;
            p.area_pdf = 1.0f / area();
        } else {
            p.position = point;
            p.normal = glm::vec3(0.0f);
            p.radiance = intensity;
            p.area_pdf = 1.0f;
            p.is_delta = true;
        }
        return p;
    }
};

// The rectangle along a ray (nothing occludes; the point light cannot be hit).
struct RectangleQuery {
    const TwoLights* lights;
    restir::LightHit find_light(glm::vec3 origin, glm::vec3 direction) const {
        const glm::vec3 n = lights->normal();
        const float denominator = glm::dot(n, direction);
        if (denominator == 0.0f)
            return {};
        const float t = glm::dot(n, lights->corner - origin) / denominator;
        const glm::vec3 p = origin + t * direction - lights->corner;
        const float u = glm::dot(p, lights->edge0) / glm::dot(lights->edge0, lights->edge0);
        const float v = glm::dot(p, lights->edge1) / glm::dot(lights->edge1, lights->edge1);
        if (!(t > 0.0f) || u < 0.0f || u > 1.0f || v < 0.0f || v > 1.0f)
            return {};
        restir::LightHit hit{true, 0u, lights->sample_point(0u, {u, v})};
        hit.point.position = origin + t * direction;
        if (denominator > 0.0f) // the back of the emitter
            hit.point.radiance = glm::vec3(0.0f);
        return hit;
    }
};

// A Lambertian receiver that samples its cosine lobe.
struct CosineReceiver {
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f, 1.0f, 0.0f};
    glm::vec3 albedo{0.7f, 0.5f, 0.3f};
    glm::vec3 reflected(glm::vec3 wi) const {
        return albedo * (restir::inv_pi * std::max(0.0f, glm::dot(normal, wi)));
    }
    restir::DirectionSample sample_direction(float, float u0, float u1) const {
        const glm::vec3 wi = restir::sample_diffuse_direction(normal, u0, u1);
        return {wi, restir::diffuse_direction_pdf(normal, wi)};
    }
    float direction_pdf(glm::vec3 wi) const { return restir::diffuse_direction_pdf(normal, wi); }
};

// Le f G over the rectangle by the midpoint rule on a grid of n x n cells, plus the point light.
template <class R>
glm::dvec3 truth(const TwoLights& lights, const R& receiver, bool with_point, int n) {
    glm::dvec3 sum(0.0);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const restir::LightSample p =
                lights.sample_point(0u, {(static_cast<float>(i) + 0.5f) / static_cast<float>(n),
                                         (static_cast<float>(j) + 0.5f) / static_cast<float>(n)});
            const glm::vec3 x = p.position - receiver.position;
            const float d2 = glm::dot(x, x);
            const glm::vec3 wi = x / std::sqrt(d2);
            const float cos_light = std::max(0.0f, -glm::dot(p.normal, wi));
            sum += glm::dvec3(p.radiance * receiver.reflected(wi) * (cos_light / d2));
        }
    sum *= static_cast<double>(lights.area()) / (static_cast<double>(n) * n);
    if (with_point) {
        const glm::vec3 x = lights.point - receiver.position;
        const float d2 = glm::dot(x, x);
        sum += glm::dvec3(lights.intensity * receiver.reflected(x / std::sqrt(d2)) / d2);
    }
    return sum;
}

// The mean of f(y) W over 40000 independent reservoirs `resample(rng)` at `receiver`, per
// channel, f shaded with `visible(sample)`, against `exact`: within 4 SE.
template <class R, class Resample, class Visible>
void expect_mean_of(const R& receiver, const Resample& resample, const Visible& visible,
                    glm::dvec3 exact, const std::string& label) {
    RunningStats stats[3];
    constexpr std::uint32_t trials = 40000u;
    for (std::uint32_t t = 0; t < trials; ++t) {
        restir::Pcg32 rng = restir::make_pixel_rng(t, 0u, 0u, 7u);
        const restir::Reservoir<restir::LightPointSample> r = resample(rng);
        const glm::vec3 estimate =
            r.has_sample() && visible(r.sample)
                ? restir::unshadowed_radiance(r.sample, receiver) * r.contribution_weight
                : glm::vec3(0.0f);
        for (int c = 0; c < 3; ++c)
            stats[c].add(static_cast<double>(estimate[c]));
    }
    for (int c = 0; c < 3; ++c) {
        EXPECT_GT(exact[c], 0.0) << label;
        EXPECT_LT(std::abs(stats[c].mean() - exact[c]), 4.0 * stats[c].standard_error())
            << label << " channel " << c << ": mean " << stats[c].mean() << " truth " << exact[c]
            << " SE " << stats[c].standard_error();
    }
}

// expect_mean_of with resample_lights_and_bsdf, lights drawn uniformly.
template <restir::LightPoints Points = restir::LightPoints::area, class Lights, class Query,
          class R, class Visible>
void expect_mean(const Lights& lights, const Query& query, const R& receiver,
                 restir::CandidateCounts counts, const Visible& visible, glm::dvec3 exact,
                 const std::string& label) {
    const restir::UniformLightSampler sampler{lights.light_count()};
    const restir::ShadingPoint at{receiver.position, receiver.normal, 0.0f};
    expect_mean_of(
        receiver,
        [&](restir::Pcg32& rng) {
            return restir::resample_lights_and_bsdf<restir::ChannelNorm::euclidean, Points>(
                rng, counts, sampler, at, lights, restir::Falloff::exact(), receiver, query);
        },
        visible, exact, label);
}

template <class R>
void expect_unbiased(const TwoLights& lights, const R& receiver, restir::CandidateCounts counts,
                     const std::string& label) {
    expect_mean(
        lights, RectangleQuery{&lights}, receiver, counts,
        [](const restir::LightPointSample&) { return true; },
        truth(lights, receiver, glm::length(lights.intensity) > 0.0f, 1024), label);
}

TEST(BsdfCandidates, UnbiasedAtADiffuseReceiverForEachMixOfStrategies) {
    TwoLights lights;
    const CosineReceiver receiver{{0.1f, 0.0f, 0.2f}, {0.0f, 1.0f, 0.0f}, {0.7f, 0.5f, 0.3f}};
    expect_unbiased(lights, receiver, {8u, 0u}, "lights only");
    expect_unbiased(lights, receiver, {4u, 2u}, "lights and BSDF");
    lights.intensity = glm::vec3(0.0f); // BSDF rays alone cannot reach a point light
    expect_unbiased(lights, receiver, {0u, 4u}, "BSDF only");
}

TEST(BsdfCandidates, UnbiasedAtGlossyReceivers) {
    TwoLights lights;
    const glm::vec3 wo = glm::normalize(glm::vec3(-0.6f, 1.0f, -0.1f));
    for (const float roughness : {0.05f, 0.3f, 1.0f}) {
        restir::GlossyReceiver receiver{{0.1f, 0.0f, 0.2f}, {0.0f, 1.0f, 0.0f}, wo, {}};
        receiver.bsdf =
            restir::GlossyBsdf::from_metallic_roughness({0.8f, 0.6f, 0.4f}, 0.0f, roughness);
        const std::string name = "roughness " + std::to_string(roughness);
        expect_unbiased(lights, receiver, {8u, 0u}, name + ", lights only");
        expect_unbiased(lights, receiver, {4u, 2u}, name + ", lights and BSDF");
        restir::GlossyReceiver metal = receiver;
        metal.bsdf =
            restir::GlossyBsdf::from_metallic_roughness({0.9f, 0.7f, 0.5f}, 1.0f, roughness);
        expect_unbiased(lights, metal, {4u, 2u}, name + ", metal, lights and BSDF");
    }
}

} // namespace

namespace {

// TwoLights with a sky as light 2: a distant light of radiance sky(w) = (0.3 + 4 max(0, s.w)^16)
// times a colour, sampled uniformly over the sphere (pdf 1 / (4 pi) per steradian). The
// rectangle hides the sky behind it: BSDF rays that hit it find the rectangle, and light
// candidates towards the sky behind it are shadowed.
struct LightsAndSky : TwoLights {
    glm::vec3 sun = glm::normalize(glm::vec3(0.4f, 0.8f, -0.3f));
    glm::vec3 sky_colour{0.4f, 0.6f, 1.0f};

    glm::vec3 sky(glm::vec3 w) const {
        return sky_colour * (0.3f + 4.0f * std::pow(std::max(0.0f, glm::dot(sun, w)), 16.0f));
    }
    std::uint32_t light_count() const { return 3u; }
    restir::LightSample sample_point(std::uint32_t id, glm::vec2 uv) const {
        if (id < 2u)
            return TwoLights::sample_point(id, uv);
        const float z = 1.0f - 2.0f * uv.x;
        const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
        const float phi = 2.0f * restir::pi * uv.y;
        restir::LightSample p;
        p.position = {r * std::cos(phi), z, r * std::sin(phi)};
        p.normal = glm::vec3(0.0f);
        p.radiance = sky(p.position);
        p.area_pdf = 1.0f / (4.0f * restir::pi);
        p.is_distant = true;
        return p;
    }
};

// The rectangle along a ray, else the sky.
struct RectangleOrSkyQuery {
    const LightsAndSky* lights;
    restir::LightHit find_light(glm::vec3 origin, glm::vec3 direction) const {
        const restir::LightHit hit = RectangleQuery{lights}.find_light(origin, direction);
        if (hit.found)
            return hit;
        restir::LightSample sky;
        sky.position = direction;
        sky.normal = glm::vec3(0.0f);
        sky.radiance = lights->sky(direction);
        sky.area_pdf = 1.0f / (4.0f * restir::pi);
        sky.is_distant = true;
        return {true, 2u, sky};
    }
};

// Whether the rectangle blocks the sky along `direction` from `origin`.
bool rectangle_blocks(const LightsAndSky& lights, glm::vec3 origin, glm::vec3 direction) {
    return RectangleQuery{&lights}.find_light(origin, direction).found;
}

// The rectangle and the point light as `truth` has them, plus the sky where the rectangle does
// not hide it, by the midpoint rule over (phi, cos theta) on n x n cells (d omega = d phi dz).
template <class R>
glm::dvec3 truth_with_sky(const LightsAndSky& lights, const R& receiver, int n) {
    return truth(lights, receiver, true, 1024) +
           restir::test::integrate_over_sphere<glm::dvec3>(n, [&](glm::vec3 w) {
               return rectangle_blocks(lights, receiver.position, w)
                          ? glm::dvec3(0.0)
                          : glm::dvec3(lights.sky(w) * receiver.reflected(w));
           });
}

// Light and BSDF candidates over the rectangle, the point light and the sky, shaded with the
// sky's visibility: unbiased in the mixed measures (area for the rectangle, solid angle for the
// sky, counting for the point).
template <class R>
void expect_unbiased_with_sky(const LightsAndSky& lights, const R& receiver,
                              restir::CandidateCounts counts, const std::string& label) {
    expect_mean(
        lights, RectangleOrSkyQuery{&lights}, receiver, counts,
        [&](const restir::LightPointSample& s) {
            return !s.is_distant() || !rectangle_blocks(lights, receiver.position, s.position);
        },
        truth_with_sky(lights, receiver, 1024), label);
}

TEST(BsdfCandidates, UnbiasedWithASkyBesideAreaAndPointLights) {
    const LightsAndSky lights;
    const CosineReceiver diffuse{{0.1f, 0.0f, 0.2f}, {0.0f, 1.0f, 0.0f}, {0.7f, 0.5f, 0.3f}};
    expect_unbiased_with_sky(lights, diffuse, {8u, 0u}, "diffuse, lights only");
    expect_unbiased_with_sky(lights, diffuse, {4u, 2u}, "diffuse, lights and BSDF");
    const glm::vec3 wo = glm::normalize(glm::vec3(-0.6f, 1.0f, -0.1f));
    for (const float roughness : {0.1f, 0.5f}) {
        restir::GlossyReceiver glossy{{0.1f, 0.0f, 0.2f}, {0.0f, 1.0f, 0.0f}, wo, {}};
        glossy.bsdf =
            restir::GlossyBsdf::from_metallic_roughness({0.8f, 0.6f, 0.4f}, 0.5f, roughness);
        const std::string name = "roughness " + std::to_string(roughness);
        expect_unbiased_with_sky(lights, glossy, {8u, 0u}, name + ", lights only");
        expect_unbiased_with_sky(lights, glossy, {4u, 2u}, name + ", lights and BSDF");
    }
}

} // namespace

namespace {

// TwoLights whose rectangle also draws its points from a receiver, uniform in the solid angle
// it subtends (restir::sample_rectangle_from), with that map's density per unit area
// (`ReceiverLightDensity`).
struct TwoLightsFromReceiver : TwoLights {
    using TwoLights::sample_point;
    restir::LightSample sample_point(std::uint32_t id, glm::vec2 uv, glm::vec3 from) const {
        restir::LightSample p = TwoLights::sample_point(id, uv);
        if (id == 0u) {
            const restir::SolidAngleSample s =
                restir::sample_rectangle_from(from, corner, edge0, edge1, uv);
            p.position = s.point;
            p.area_pdf = restir::solid_angle_to_area_pdf(s.pdf, from, s.point, normal());
        }
        return p;
    }
    float point_pdf(std::uint32_t id, glm::vec3 on_light, glm::vec3 from) const {
        if (id != 0u)
            return 1.0f;
        return restir::solid_angle_to_area_pdf(
            restir::rectangle_pdf_from(from, corner, edge0, edge1, on_light), from, on_light,
            normal());
    }
};
static_assert(restir::ReceiverLightDensity<TwoLightsFromReceiver>);
static_assert(!restir::ReceiverLightDensity<TwoLights>);

// Light points drawn from the receiver, combined with BSDF candidates by MIS in the measure the
// light strategy sampled (LightPoints::from_receiver): unbiased at diffuse and glossy
// receivers, near the light too, where area points make the candidates' weights unbounded.
TEST(BsdfCandidates, UnbiasedWithLightPointsDrawnFromTheReceiver) {
    TwoLightsFromReceiver lights;
    constexpr auto from_receiver = restir::LightPoints::from_receiver;
    const auto always = [](const restir::LightPointSample&) { return true; };
    for (const float height : {0.0f, 0.9f}) { // the light 1 and 0.1 above the receiver
        const std::string at = "height " + std::to_string(height);
        const CosineReceiver diffuse{{0.1f, height, 0.2f}, {0.0f, 1.0f, 0.0f}, {0.7f, 0.5f, 0.3f}};
        const glm::dvec3 exact = truth(lights, diffuse, true, 1024);
        expect_mean<from_receiver>(lights, RectangleQuery{&lights}, diffuse, {8u, 0u}, always,
                                   exact, at + ", diffuse, lights only");
        expect_mean<from_receiver>(lights, RectangleQuery{&lights}, diffuse, {4u, 2u}, always,
                                   exact, at + ", diffuse, lights and BSDF");
        const glm::vec3 wo = glm::normalize(glm::vec3(-0.6f, 1.0f, -0.1f));
        restir::GlossyReceiver glossy{{0.1f, height, 0.2f}, {0.0f, 1.0f, 0.0f}, wo, {}};
        glossy.bsdf = restir::GlossyBsdf::from_metallic_roughness({0.8f, 0.6f, 0.4f}, 0.5f, 0.2f);
        expect_mean<from_receiver>(lights, RectangleQuery{&lights}, glossy, {4u, 2u}, always,
                                   truth(lights, glossy, true, 1024),
                                   at + ", glossy, lights and BSDF");
    }
}

} // namespace

// BSDF candidates beside candidates from a light tile (restir::resample_tiles_and_bsdf). Every
// trial refills one tile of 32 entries by power (powers 3 : 1 : 2, so the tiles' pmf is not the
// uniform one of the other tests) and takes `counts.light` of them in groups of 8 from a random
// group on: each entry is uniformly random, so unbiased over the trials.
namespace {

template <class Lights, class Query, class R, class Visible>
void expect_tile_mean(const Lights& lights, const Query& query, const R& receiver,
                      restir::CandidateCounts counts, const Visible& visible, glm::dvec3 exact,
                      const std::string& label) {
    constexpr std::uint32_t group = 8u, size = 32u;
    const float powers[] = {3.0f, 1.0f, 2.0f};
    const restir::AliasTable table(std::span<const float>(powers, lights.light_count()));
    const restir::PowerLightSampler source{table.view()};
    std::vector<float> planes(size * restir::tile_plane_count);
    std::vector<restir::LightSampleRef> references(size);
    const restir::LightTileArrays tiles{planes.data(), references.data(), 1u, size};
    std::uint32_t trial = 0u;
    expect_mean_of(
        receiver,
        [&](restir::Pcg32& rng) {
            restir::presample_lights(
                source, lights, size,
                [&](std::uint32_t k) { return restir::make_pixel_rng(k, trial, 1u, 7u); },
                [&](std::uint32_t k, const restir::PresampledLight& e) {
                    tiles.store(0u, k, e, restir::Falloff::exact());
                });
            ++trial;
            const std::uint32_t start = rng.next_uint();
            return restir::resample_tiles_and_bsdf<group, restir::ChannelNorm::euclidean>(
                rng, counts, tiles,
                [&](std::uint32_t g) { return (start + g) % (size / group) * group; }, source,
                restir::Falloff::exact(), receiver, query);
        },
        visible, exact, label);
}

TEST(TileBsdfCandidates, UnbiasedWithAreaAndPointLights) {
    TwoLights lights;
    const CosineReceiver diffuse{{0.1f, 0.0f, 0.2f}, {0.0f, 1.0f, 0.0f}, {0.7f, 0.5f, 0.3f}};
    const glm::vec3 wo = glm::normalize(glm::vec3(-0.6f, 1.0f, -0.1f));
    const auto all = [](const restir::LightPointSample&) { return true; };
    for (const restir::CandidateCounts counts :
         {restir::CandidateCounts{8u, 0u}, {8u, 1u}, {16u, 2u}}) {
        const std::string mix =
            std::to_string(counts.light) + " tile + " + std::to_string(counts.bsdf) + " BSDF";
        expect_tile_mean(lights, RectangleQuery{&lights}, diffuse, counts, all,
                         truth(lights, diffuse, true, 1024), "diffuse, " + mix);
        for (const float roughness : {0.05f, 0.3f}) {
            restir::GlossyReceiver glossy{{0.1f, 0.0f, 0.2f}, {0.0f, 1.0f, 0.0f}, wo, {}};
            glossy.bsdf =
                restir::GlossyBsdf::from_metallic_roughness({0.9f, 0.7f, 0.5f}, 1.0f, roughness);
            expect_tile_mean(lights, RectangleQuery{&lights}, glossy, counts, all,
                             truth(lights, glossy, true, 1024),
                             "metal " + std::to_string(roughness) + ", " + mix);
        }
    }
}

TEST(TileBsdfCandidates, UnbiasedWithASky) {
    const LightsAndSky lights;
    const glm::vec3 wo = glm::normalize(glm::vec3(-0.6f, 1.0f, -0.1f));
    restir::GlossyReceiver glossy{{0.1f, 0.0f, 0.2f}, {0.0f, 1.0f, 0.0f}, wo, {}};
    glossy.bsdf = restir::GlossyBsdf::from_metallic_roughness({0.8f, 0.6f, 0.4f}, 0.5f, 0.2f);
    expect_tile_mean(
        lights, RectangleOrSkyQuery{&lights}, glossy, {8u, 2u},
        [&](const restir::LightPointSample& s) {
            return !s.is_distant() || !rectangle_blocks(lights, glossy.position, s.position);
        },
        truth_with_sky(lights, glossy, 1024), "glossy, 8 tile + 2 BSDF, sky");
}

} // namespace
