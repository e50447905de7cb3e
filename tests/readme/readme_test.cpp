// The README's snippets compile together (the build) and run on stub inputs without
// tripping an assertion or a sanitizer.
#include "readme/prelude.hpp"

#include <gtest/gtest.h>

namespace {

TEST(Readme, SnippetsCompileTogetherAndRun) {
    readme::Frame frame;
    frame.snippets(); // fails in the sanitised debug build on any assertion or bad access
}

} // namespace
