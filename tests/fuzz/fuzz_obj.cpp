// libFuzzer target: OBJ text (before the first NUL byte) and MTL text (after it) through the
// scene loader, then the automatic camera framing. Refusals are SceneErrors; anything else
// (a crash, a sanitizer report, another exception, a camera that passes its check but gives
// non-finite rays) is a finding.
#include "camera.hpp"
#include "scene.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view input(reinterpret_cast<const char*>(data), size);
    const std::size_t split = input.find('\0');
    const std::string_view obj = input.substr(0, split);
    const std::string_view mtl =
        split == std::string_view::npos ? std::string_view{} : input.substr(split + 1);
    try {
        const pt::Scene scene = pt::parse_obj(obj, mtl, "fuzz.obj");
        const pt::CameraSetup setup = pt::frame_bounds(scene, 1.5f);
        pt::check_camera(setup);
        const pt::Camera camera(setup, 48, 32);
        for (const glm::vec2 pixel :
             {glm::vec2(0.0f), glm::vec2(24.0f, 16.0f), glm::vec2(48, 32)}) {
            const glm::vec3 d = camera.direction(pixel);
            if (!std::isfinite(d.x) || !std::isfinite(d.y) || !std::isfinite(d.z))
                __builtin_trap(); // the check passed a camera that cannot form rays
        }
    } catch (const pt::SceneError&) {
    }
    return 0;
}
