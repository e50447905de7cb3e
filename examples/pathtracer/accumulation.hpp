// The frames of a render: the last one alone, their sum in double precision and its average.
#pragma once

#include "image_io.hpp"

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace pt {

/// The last frame and the average of all frames so far.
class Accumulation {
public:
    Accumulation(std::uint32_t width, std::uint32_t height)
        : frame_(width, height), average_(width, height),
          sum_(std::size_t{width} * height, glm::dvec3(0.0)) {}

    /// The frame being rendered (after add_frame: the last frame).
    Image& frame() { return frame_; }
    const Image& frame() const { return frame_; }
    /// The average of the frames added.
    const Image& average() const { return average_; }
    /// Frames added so far.
    std::uint32_t frames() const { return frames_; }

    /// Adds the frame image to the sum; the average is the sum's.
    void add_frame() {
        ++frames_;
        const double inverse = 1.0 / frames_;
        for (std::size_t i = 0; i < sum_.size(); ++i) {
            sum_[i] += glm::dvec3(frame_.pixels[i]);
            average_.pixels[i] = glm::vec3(sum_[i] * inverse);
        }
    }

private:
    Image frame_, average_;
    std::vector<glm::dvec3> sum_;
    std::uint32_t frames_ = 0;
};

} // namespace pt
