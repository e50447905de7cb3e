// Sphere lights in the example renderer (shape_sphere.hpp through the light-shape seam): the
// emitters' points drawn by solid angle and by area estimate the analytic irradiance of a
// uniform sphere, Embree finds spheres with their outward normal, bad spheres are refused, and
// every method renders the analytic radiance of a floor under two spheres and agrees with the
// path-traced reference in the Cornell box lit by spheres.
#include "embree_scene.hpp"
#include "lights.hpp"
#include "renderer.hpp"
#include "scene.hpp"
#include "scene_quad.hpp"

#include "pathtracer/directional_albedo.hpp"
#include "pathtracer/image_sums.hpp"
#include "support/statistics.hpp"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace {

using pt::GlobalIllumination;
using pt::LightPoints;
using pt::Method;

constexpr double pi = 3.14159265358979323846;

// A large Lambertian floor (y = 0, facing up, albedo 0.6) under two emissive spheres, each
// wholly above the floor's plane and unoccluded from `seen`, the point the camera's single
// pixel looks at.
const glm::vec3 seen{0.3f, 0.0f, 0.2f};
const pt::Sphere lamps[2] = {{{0.0f, 1.5f, 0.0f}, 0.4f, 1u}, {{1.6f, 0.9f, 0.8f}, 0.25f, 2u}};
const glm::vec3 lamp_radiance[2] = {{2.0f, 1.0f, 0.5f}, {1.0f, 3.0f, 4.0f}};
constexpr float floor_albedo = 0.6f;

pt::Scene floor_under_spheres(const pt::Material& floor) {
    pt::Scene scene;
    scene.name = "floor-under-spheres";
    scene.materials = {floor,
                       {.name = "lamp-a", .albedo = glm::vec3(0.5f), .emission = lamp_radiance[0]},
                       {.name = "lamp-b", .albedo = glm::vec3(0.5f), .emission = lamp_radiance[1]}};
    pt::add_quad(scene,
                 {{{-20.0f, 0.0f, -20.0f},
                   {20.0f, 0.0f, -20.0f},
                   {20.0f, 0.0f, 20.0f},
                   {-20.0f, 0.0f, 20.0f}}},
                 {0.0f, 1.0f, 0.0f}, 0u);
    for (const pt::Sphere& lamp : lamps)
        scene.shapes.add(lamp);
    // Looking down at `seen` from the side away from both spheres.
    scene.camera = pt::CameraSetup{seen + glm::vec3(0.4f, 1.2f, -1.5f), seen, {0, 1, 0}, 20.0f};
    return scene;
}

// Irradiance at a receiver from a uniform sphere wholly above its horizon: pi L (r / d)^2 cos
// theta, theta between the normal and the direction to the centre (the sphere is a point of
// intensity L pi r^2 in that direction, exactly, for a cosine receiver).
double sphere_irradiance(const pt::Sphere& sphere, double radiance, glm::dvec3 at,
                         glm::dvec3 normal) {
    const glm::dvec3 axis = glm::dvec3(sphere.centre) - at;
    const double d = glm::length(axis);
    const double r = static_cast<double>(sphere.radius);
    return pi * radiance * (r / d) * (r / d) * glm::dot(normal, axis / d);
}

// One sample of the irradiance at (`at`, `normal`) from light point `p`: L cos cos' / (d^2
// p_area), one-sided at the light.
double irradiance_sample(const restir::LightSample& p, glm::vec3 at, glm::vec3 normal) {
    const glm::dvec3 offset = glm::dvec3(p.position) - glm::dvec3(at);
    const double d2 = glm::dot(offset, offset);
    const glm::dvec3 w = offset / std::sqrt(d2);
    const double cos_receiver = std::max(0.0, glm::dot(glm::dvec3(normal), w));
    const double cos_light = std::max(0.0, -glm::dot(glm::dvec3(p.normal), w));
    if (!(p.area_pdf > 0.0f))
        return 0.0;
    return static_cast<double>(p.radiance.x) * cos_receiver * cos_light /
           (d2 * static_cast<double>(p.area_pdf));
}

// The emitters' points of one sphere, drawn by solid angle (SceneEmitters::sample_point with a
// receiver, the library's sphere_light.hpp) and by area, each estimate the analytic irradiance
// within 4 standard errors measured over 40000 trials; the solid-angle points lie on the
// visible cap, their density is point_pdf's, and next to the sphere their estimate is far less
// noisy than the area points'.
TEST(SphereLight, SolidAngleAndAreaPointsEstimateTheAnalyticIrradiance) {
    pt::Scene scene = floor_under_spheres({.name = "floor"});
    const pt::SceneEmitters emitters(scene);
    ASSERT_EQ(emitters.light_count(), 2u);
    ASSERT_TRUE(emitters.is_shape(0u));
    struct Receiver {
        const char* name;
        glm::vec3 at, normal;
    };
    const pt::Sphere& sphere = lamps[0];
    const Receiver receivers[] = {
        {"near, facing", {0.0f, 0.95f, 0.0f}, {0.0f, 1.0f, 0.0f}},
        {"far, facing", {0.0f, -6.5f, 0.1f}, {0.0f, 1.0f, 0.0f}},
        {"tilted", {0.9f, 0.6f, 0.3f}, glm::normalize(glm::vec3(-0.2f, 1.0f, 0.4f))}};
    for (const Receiver& r : receivers) {
        const double truth = sphere_irradiance(sphere, 2.0, glm::dvec3(r.at), glm::dvec3(r.normal));
        restir::test::RunningStats solid_angle, area;
        restir::Pcg32 rng = restir::make_pixel_rng(5u, 9u, 1u);
        int off_cap = 0, wrong_pdf = 0;
        for (int k = 0; k < 40000; ++k) {
            const glm::vec2 uv{restir::next_float(rng), restir::next_float(rng)};
            const restir::LightSample drawn = emitters.sample_point(0u, uv, r.at);
            solid_angle.add(irradiance_sample(drawn, r.at, r.normal));
            area.add(irradiance_sample(emitters.sample_point(0u, uv), r.at, r.normal));
            const float pdf = emitters.point_pdf(0u, drawn.position, r.at);
            wrong_pdf += std::abs(pdf - drawn.area_pdf) > 1e-4f * drawn.area_pdf;
            off_cap += glm::dot(drawn.normal, r.at - drawn.position) < -1e-5f;
        }
        std::printf("%s: truth %.6f, solid angle %.6f +- %.6f, area %.6f +- %.6f\n", r.name, truth,
                    solid_angle.mean(), solid_angle.standard_error(), area.mean(),
                    area.standard_error());
        EXPECT_TRUE(restir::test::agrees_with(solid_angle, truth)) << r.name;
        EXPECT_TRUE(restir::test::agrees_with(area, truth)) << r.name;
        EXPECT_EQ(off_cap, 0) << r.name;
        EXPECT_EQ(wrong_pdf, 0) << r.name;
        if (std::string(r.name) == "near, facing") {
            EXPECT_LT(solid_angle.standard_error(), 0.25 * area.standard_error());
        }
    }
}

// A receiver inside the sphere sees its inside, which sends nothing: no point, density 0.
TEST(SphereLight, NoPointFromInsideTheSphere) {
    const pt::SceneEmitters emitters(floor_under_spheres({.name = "floor"}));
    const restir::LightSample p = emitters.sample_point(0u, {0.3f, 0.7f}, lamps[0].centre);
    EXPECT_EQ(p.area_pdf, 0.0f);
    EXPECT_EQ(p.radiance, glm::vec3(0.0f));
}

// Embree finds a sphere (user geometry) at the right distance with its outward normal, from
// outside and from inside, misses it beside, and answers packets as single rays; shadow segments
// through it are blocked and those that stop short are not; hits number the spheres after the
// triangles.
TEST(SphereLight, RaysFindTheSphereWithItsOutwardNormal) {
    const pt::Scene scene = floor_under_spheres({.name = "floor"});
    const pt::EmbreeScene rays(scene);
    const pt::Sphere& sphere = lamps[0];
    const glm::vec3 from = sphere.centre + glm::vec3(0.0f, 0.0f, -3.0f);
    const pt::Hit outside = rays.closest_hit(from, {0.0f, 0.0f, 2.0f});
    ASSERT_TRUE(outside.found);
    EXPECT_EQ(outside.primitive, scene.triangle_count());
    EXPECT_EQ(scene.material_of(outside.primitive), 1u);
    EXPECT_NEAR(outside.distance, 3.0f - sphere.radius, 1e-5f);
    EXPECT_NEAR(glm::dot(outside.normal, glm::vec3(0.0f, 0.0f, -1.0f)), 1.0f, 1e-6f);
    const pt::Hit inside = rays.closest_hit(sphere.centre, {1.0f, 0.0f, 0.0f});
    ASSERT_TRUE(inside.found);
    EXPECT_NEAR(inside.distance, sphere.radius, 1e-5f);
    EXPECT_NEAR(inside.normal.x, 1.0f, 1e-6f);
    const pt::Hit beside =
        rays.closest_hit(from + glm::vec3(0.0f, 1.01f * sphere.radius, 0.0f), {0.0f, 0.0f, 1.0f});
    EXPECT_FALSE(beside.found && beside.primitive == outside.primitive);
    const pt::Hit floor = rays.closest_hit(seen + glm::vec3(0.0f, 0.1f, 0.0f), {0, -1.0f, 0});
    EXPECT_LT(floor.primitive, scene.triangle_count());
    EXPECT_EQ(scene.material_of(floor.primitive), 0u);

    std::vector<glm::vec3> directions;
    for (int k = 0; k < 37; ++k) // more than two packets, rays hitting, grazing and missing
        directions.push_back(glm::normalize(sphere.centre - from +
                                            glm::vec3(0.03f * static_cast<float>(k - 18), 0, 0)));
    std::vector<pt::Hit> packed(directions.size());
    rays.closest_hits(from, directions, packed);
    for (std::size_t k = 0; k < directions.size(); ++k) {
        const pt::Hit single = rays.closest_hit(from, directions[k]);
        EXPECT_EQ(single.found, packed[k].found) << k;
        EXPECT_EQ(single.primitive, packed[k].primitive) << k;
        EXPECT_EQ(single.distance, packed[k].distance) << k;
    }
    EXPECT_TRUE(rays.occluded(from, sphere.centre + glm::vec3(0.0f, 0.0f, 3.0f)));
    EXPECT_FALSE(rays.occluded(from, from + glm::vec3(0.0f, 0.0f, 2.5f)));
    const std::array<glm::vec3, 2> ends{sphere.centre, from + glm::vec3(0.0f, 0.0f, 2.5f)};
    const std::array<glm::vec3, 2> starts{from, from};
    std::array<std::uint8_t, 2> blocked{};
    rays.occluded_segments(starts, ends, blocked);
    EXPECT_EQ(blocked[0], 1u);
    EXPECT_EQ(blocked[1], 0u);
}

// A sphere that cannot be rendered is refused with one line naming it and why.
TEST(SphereLight, BadSpheresAreRefusedWithAClearMessage) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    struct Bad {
        pt::Sphere sphere;
        const char* reason;
    };
    const Bad bad[] = {
        {{{0.0f, 1.0f, 0.0f}, 0.0f, 1u}, "radius"}, {{{0.0f, 1.0f, 0.0f}, -1.0f, 1u}, "radius"},
        {{{0.0f, 1.0f, 0.0f}, nan, 1u}, "radius"},  {{{nan, 1.0f, 0.0f}, 1.0f, 1u}, "box"},
        {{{2e15f, 1.0f, 0.0f}, 1.0f, 1u}, "1e15"},  {{{0.0f, 1.0f, 0.0f}, 1.0f, 7u}, "material"}};
    for (const Bad& b : bad) {
        pt::Scene scene = floor_under_spheres({.name = "floor"});
        scene.shapes.add(b.sphere);
        const std::string expected = "sphere 2 of scene 'floor-under-spheres' cannot be rendered";
        for (int built = 0; built < 2; ++built) {
            try {
                if (built == 0)
                    pt::EmbreeScene{scene};
                else
                    pt::Renderer(scene, pt::RenderSettings{});
                ADD_FAILURE() << "accepted: " << b.reason;
            } catch (const pt::SceneError& e) {
                const std::string what = e.what();
                EXPECT_NE(what.find(expected), std::string::npos) << what;
                EXPECT_NE(what.find(b.reason), std::string::npos) << what;
            }
        }
    }
}

// The one-pixel render of the floor at `seen` by `method`, its light points `points`.
pt::RenderSettings one_pixel(const pt::Scene& scene, Method method, LightPoints points) {
    pt::RenderSettings s;
    s.width = 1;
    s.height = 1;
    s.camera = *scene.camera;
    s.gi = GlobalIllumination::none;
    s.method = method;
    s.light_points = points;
    s.candidates = 8;
    s.threads = 2;
    return s;
}

// Every method estimates the analytic radiance of a Lambertian floor under two spheres:
// albedo / pi times the sum of their irradiance, within 4 standard errors measured over
// independent frames (over independent renders for ReSTIR, whose frames share history).
TEST(SphereLight, EveryMethodRendersTheAnalyticRadiance) {
    const pt::Scene scene =
        floor_under_spheres({.name = "floor", .albedo = glm::vec3(floor_albedo)});
    glm::dvec3 truth(0.0);
    for (int k = 0; k < 2; ++k)
        for (int c = 0; c < 3; ++c)
            truth[c] += static_cast<double>(floor_albedo) / pi *
                        sphere_irradiance(lamps[k], static_cast<double>(lamp_radiance[k][c]),
                                          glm::dvec3(seen), {0.0, 1.0, 0.0});
    struct Run {
        Method method;
        pt::CandidateSource source;
        LightPoints points;
        const char* name;
    };
    const Run runs[] = {
        {Method::reference, pt::CandidateSource::automatic, LightPoints::automatic, "reference"},
        {Method::uniform, pt::CandidateSource::automatic, LightPoints::automatic, "uniform"},
        {Method::uniform, pt::CandidateSource::automatic, LightPoints::area, "uniform area"},
        {Method::ris, pt::CandidateSource::power, LightPoints::automatic, "ris power"},
        {Method::ris, pt::CandidateSource::power, LightPoints::area, "ris power area"},
        {Method::ris, pt::CandidateSource::bvh, LightPoints::automatic, "ris bvh"},
        {Method::ris, pt::CandidateSource::bvh, LightPoints::area, "ris bvh area"},
        {Method::restir, pt::CandidateSource::power, LightPoints::automatic, "restir"},
        {Method::restir, pt::CandidateSource::bvh, LightPoints::area, "restir bvh area"}};
    for (const Run& run : runs) {
        pt::RenderSettings s = one_pixel(scene, run.method, run.points);
        s.source = run.source;
        pt::test::ChannelStats radiance;
        if (run.method == Method::restir) {
            for (std::uint64_t seed = 1; seed <= 96; ++seed) {
                s.seed = seed;
                pt::Renderer renderer(scene, s);
                renderer.render_frame();
                renderer.render_frame();
                for (int c = 0; c < 3; ++c)
                    radiance[c].add(static_cast<double>(renderer.last_frame().pixels[0][c]));
            }
        } else {
            pt::Renderer renderer(scene, s);
            radiance = pt::test::pixel_radiance(renderer, 160);
        }
        for (int c = 0; c < 3; ++c) {
            std::printf("%-16s channel %d: %.5f +- %.5f, analytic %.5f\n", run.name, c,
                        radiance[c].mean(), radiance[c].standard_error(), truth[c]);
            EXPECT_TRUE(restir::test::agrees_with(radiance[c], truth[c])) << run.name << " " << c;
        }
    }
}

// `auto` light points are drawn by solid angle in a scene with light shapes, from the light
// BVH (by area from light tiles with a packed history, which decodes area points), by area in
// a scene of triangles; with area points a packed history gives the same image as the full
// one.
TEST(SphereLight, AutomaticLightPointsAndPackedHistory) {
    const pt::Scene spheres = pt::make_cornell_spheres();
    pt::RenderSettings s = one_pixel(spheres, Method::restir, LightPoints::automatic);
    s.source = pt::CandidateSource::automatic;
    const pt::RenderSettings resolved = pt::Renderer(spheres, s).settings();
    EXPECT_EQ(resolved.light_points, LightPoints::solid_angle);
    EXPECT_EQ(resolved.source, pt::CandidateSource::bvh);
    const pt::Scene box = pt::make_cornell_box();
    EXPECT_EQ(pt::Renderer(box, s).settings().light_points, LightPoints::area);
    EXPECT_EQ(pt::Renderer(box, s).settings().source, pt::CandidateSource::power);
    s.packed_history = true;
    EXPECT_EQ(pt::Renderer(spheres, s).settings().light_points, LightPoints::area);
    EXPECT_EQ(pt::Renderer(spheres, s).settings().source, pt::CandidateSource::power);

    s.width = s.height = 24;
    s.di_frame.spatial.radius = 4.0f;
    s.light_points = LightPoints::area;
    const auto render = [&](bool packed) {
        s.packed_history = packed;
        pt::Renderer renderer(spheres, s);
        for (int f = 0; f < 4; ++f)
            renderer.render_frame();
        return renderer.accumulated();
    };
    const pt::Image packed = render(true), viewed = render(false);
    ASSERT_EQ(packed.pixels.size(), viewed.pixels.size());
    EXPECT_EQ(std::memcmp(packed.pixels.data(), viewed.pixels.data(),
                          packed.pixels.size() * sizeof(glm::vec3)),
              0);
}

// The Cornell box lit by spheres, its white surfaces made glossy so that BSDF candidates join
// the light candidates: RIS and ReSTIR (points by solid angle and by area, from tiles and the
// light BVH) estimate the path-traced reference's image, the mean brightness over 8 seeds
// within 4 standard errors.
TEST(SphereLight, CornellSpheresMatchesTheReference) {
    pt::Scene scene = pt::make_cornell_spheres();
    ASSERT_EQ(scene.materials[0].name, "white");
    scene.materials[0].specular = 0.04f;
    scene.materials[0].roughness = 0.2f;
    struct Setup {
        Method method;
        LightPoints points;
        pt::CandidateSource source;
        std::string name;
    };
    const std::vector<Setup> setups = {
        {Method::reference, LightPoints::automatic, pt::CandidateSource::automatic, "reference"},
        {Method::ris, LightPoints::automatic, pt::CandidateSource::automatic, "ris"},
        {Method::ris, LightPoints::area, pt::CandidateSource::automatic, "ris area"},
        {Method::restir, LightPoints::automatic, pt::CandidateSource::automatic, "restir"},
        {Method::restir, LightPoints::area, pt::CandidateSource::bvh, "restir bvh area"}};
    pt::test::expect_agreement(scene, setups, 8, [&](const Setup& setup, std::uint64_t seed) {
        pt::RenderSettings s;
        s.width = s.height = 24;
        s.camera = *scene.camera;
        s.di_frame.spatial.radius = 4.0f;
        s.threads = 2;
        s.gi = GlobalIllumination::none;
        s.method = setup.method;
        s.light_points = setup.points;
        s.source = setup.source;
        s.bsdf_max_roughness = 1.0f;
        s.seed = seed;
        return s;
    });
}

} // namespace
