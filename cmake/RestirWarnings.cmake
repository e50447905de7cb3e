# Compiler settings for the project's own targets (tests, examples, benchmarks); consumers
# of restir::restir never see them.
add_library(restir_project_options INTERFACE)
target_compile_options(
  restir_project_options
  INTERFACE -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wdouble-promotion
            -Wnon-virtual-dtor -Wold-style-cast -Werror)
if(RESTIR_SANITIZE)
  target_compile_options(restir_project_options INTERFACE -fsanitize=address,undefined
                                                          -fno-sanitize-recover=all
                                                          -fno-omit-frame-pointer)
  target_link_options(restir_project_options INTERFACE -fsanitize=address,undefined)
endif()
