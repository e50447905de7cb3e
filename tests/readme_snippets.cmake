# Writes the ```cpp blocks of a Markdown file, in order, as the body of one function
# (readme::Frame::snippets in tests/readme/prelude.hpp), so that a test compiles and runs the
# documentation exactly as written: the blocks must fit together.
# Usage: cmake -DMARKDOWN=README.md -DOUTPUT=file.cpp -P readme_snippets.cmake
file(READ ${MARKDOWN} text)
string(REPLACE ";" "<semicolon>" text "${text}") # CMake lists split at semicolons
string(REGEX MATCHALL "```cpp\n[^`]*```" blocks "${text}")
set(body "")
foreach(block IN LISTS blocks)
  string(REGEX REPLACE "^```cpp\n" "" block "${block}")
  string(REGEX REPLACE "```$" "" block "${block}")
  string(REGEX REPLACE "#include[^\n]*\n" "" block "${block}") # the prelude includes them
  string(APPEND body "${block}")
endforeach()
string(REPLACE "<semicolon>" ";" body "${body}")
# Written every time (a copy only when different would leave the output older than README.md,
# and make would run this again on every build).
file(WRITE ${OUTPUT} "// Generated from ${MARKDOWN}: do not edit.\n#include \"readme/prelude.hpp\"\n\nvoid readme::Frame::snippets() {\n${body}}\n")
