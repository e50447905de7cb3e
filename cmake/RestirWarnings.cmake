# Compiler settings for the project's own targets (tests, examples, benchmarks); consumers
# of restir::restir never see them.
include(CheckCXXCompilerFlag)
add_library(restir_project_options INTERFACE)
target_compile_options(
  restir_project_options
  INTERFACE -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wdouble-promotion
            -Wnon-virtual-dtor -Wold-style-cast -Werror)
# sqrt without errno, so that loops calling it vectorise (docs/performance.md); the library
# never reads errno.
target_compile_options(restir_project_options INTERFACE -fno-math-errno)
# The machine's own vector width for what is built and run here (the renderer, benchmarks).
option(RESTIR_NATIVE_ARCH "Build the project's own targets with -march=native" ON)
if(RESTIR_NATIVE_ARCH)
  check_cxx_compiler_flag(-march=native restir_has_march_native)
  if(restir_has_march_native)
    target_compile_options(restir_project_options INTERFACE -march=native)
  endif()
endif()
if(RESTIR_SANITIZE)
  # float-cast-overflow: a float converted to an integer that cannot hold it (NaN, huge) is
  # undefined behaviour, and GCC's -fsanitize=undefined leaves that check out.
  target_compile_options(restir_project_options INTERFACE
                         -fsanitize=address,undefined,float-cast-overflow
                         -fno-sanitize-recover=all -fno-omit-frame-pointer)
  target_link_options(restir_project_options INTERFACE
                      -fsanitize=address,undefined,float-cast-overflow)
endif()
if(RESTIR_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "RESTIR_FUZZ needs clang (libFuzzer): -DCMAKE_CXX_COMPILER=clang++")
  endif()
  # Coverage for libFuzzer in everything we build; the fuzz executables add its main.
  target_compile_options(restir_project_options INTERFACE
                         -fsanitize=fuzzer-no-link,address,undefined,float-cast-overflow
                         -fno-sanitize-recover=all -fno-omit-frame-pointer)
  target_link_options(restir_project_options INTERFACE -fsanitize=address,undefined)
endif()
