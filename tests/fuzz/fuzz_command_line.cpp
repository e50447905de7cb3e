// libFuzzer target: restir-render's command line, the input split at NUL bytes into
// arguments. Refusals are UsageErrors; anything else (a crash, a sanitizer report, another
// exception, accepted values outside their documented ranges) is a finding.
#include "render_options.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::vector<std::string> arguments{"restir-render"};
    std::string current;
    for (std::size_t i = 0; i < size && arguments.size() < 64; ++i) {
        if (data[i] == 0) {
            arguments.push_back(current);
            current.clear();
        } else {
            current += static_cast<char>(data[i]);
        }
    }
    if (!current.empty() && arguments.size() < 64)
        arguments.push_back(current);
    std::vector<const char*> argv;
    for (const std::string& argument : arguments)
        argv.push_back(argument.c_str());

    std::string help;
    try {
        const auto options =
            pt::parse_render_options(static_cast<int>(argv.size()), argv.data(), help);
        if (!options)
            return 0;
        const pt::RenderSettings& s = options->settings;
        const bool finite =
            std::isfinite(s.di_frame.spatial.radius) && std::isfinite(s.attenuation_radius) &&
            std::isfinite(s.di_frame.boiling.threshold) &&
            (!options->fov || std::isfinite(*options->fov)) &&
            (!options->exposure || std::isfinite(*options->exposure)) &&
            std::isfinite(options->environment_scale) && options->environment_scale > 0.0f &&
            std::isfinite(options->environment_rotate);
        if (!finite || s.width == 0 || s.height == 0 || s.width > 16384 || s.height > 16384 ||
            options->frames == 0 || s.candidates > 4096u) // 0: the source's default
            __builtin_trap();                             // a value the checks should have refused
        for (const std::vector<float>* v : {&options->look_from, &options->look_at})
            for (float x : *v)
                if (!std::isfinite(x))
                    __builtin_trap();
    } catch (const pt::UsageError&) {
    }
    return 0;
}
