// The snippets of README.md and docs/integration.md compile together (the build) and run on
// stub inputs without tripping an assertion or a sanitizer.
#include "readme/integration_prelude.hpp"
#include "readme/prelude.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>

namespace {

TEST(Readme, SnippetsCompileTogetherAndRun) {
    readme::Frame frame;
    frame.snippets(); // fails in the sanitised debug build on any assertion or bad access
}

// The integration guide renders its frames, then the last frame again step by step as GPU
// kernels would, and again per tile with batched rays, then frames of a glossy floor with light
// and BSDF candidates: the images are finite and non-negative, light reaches the floor, and the
// step-by-step and tiled frames equal run_di_frame's.
TEST(Integration, SnippetsCompileTogetherAndRun) {
    integration::presented().clear();
    integration::render_frames();
    const auto& images = integration::presented();
    // Every frame of section 4, the step-by-step and tiled frames, the glossy frame of section 9.
    ASSERT_EQ(images.size(), integration::frame_count + 3u);
    for (const auto& image : images) {
        double sum = 0.0;
        for (const glm::vec3& c : image) {
            ASSERT_TRUE(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z));
            ASSERT_TRUE(c.x >= 0.0f && c.y >= 0.0f && c.z >= 0.0f);
            sum += double(c.x + c.y + c.z);
        }
        EXPECT_GT(sum, 0.0);
    }
    const auto& by_run = images[integration::frame_count - 1u];
    const auto& by_stage = images[integration::frame_count];
    const auto& by_tile = images[integration::frame_count + 1u];
    for (std::size_t i = 0; i < by_run.size(); ++i) {
        EXPECT_EQ(by_run[i], by_stage[i]) << "pixel " << i;
        EXPECT_EQ(by_run[i], by_tile[i]) << "pixel " << i;
    }
}

} // namespace
