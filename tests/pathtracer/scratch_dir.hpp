// A folder of its own for each test of the renderer: ctest runs the tests as parallel
// processes, and test names are unique across suites.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace pt_test {

/// Creates (if needed) and returns the running test's scratch folder.
inline std::filesystem::path scratch_dir() {
    const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
    const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                      "restir-pathtracer-test" /
                                      (std::string(test->test_suite_name()) + "." + test->name());
    std::filesystem::create_directories(dir);
    return dir;
}

} // namespace pt_test
