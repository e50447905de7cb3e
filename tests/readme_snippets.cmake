# Writes the ```cpp blocks of a Markdown file, in order, as compiled code, so that a test
# compiles and runs the documentation exactly as written: the blocks must fit together.
# Blocks whose first line is "// At namespace scope" (types and free functions) go before the
# function; the others, in order, form the body of FUNCTION, declared in PRELUDE.
# Usage: cmake -DMARKDOWN=README.md -DOUTPUT=file.cpp -DPRELUDE=readme/prelude.hpp
#              -DFUNCTION=readme::Frame::snippets [-DNAMESPACE=name] -P readme_snippets.cmake
file(READ ${MARKDOWN} text)
string(REPLACE ";" "<semicolon>" text "${text}") # CMake lists split at semicolons
string(REGEX MATCHALL "```cpp\n[^`]*```" blocks "${text}")
set(scope "")
set(body "")
foreach(block IN LISTS blocks)
  string(REGEX REPLACE "^```cpp\n" "" block "${block}")
  string(REGEX REPLACE "```$" "" block "${block}")
  string(REGEX REPLACE "#include[^\n]*\n" "" block "${block}") # the prelude includes them
  if(block MATCHES "^// At namespace scope")
    string(APPEND scope "${block}\n")
  else()
    string(APPEND body "${block}")
  endif()
endforeach()
string(REPLACE "<semicolon>" ";" body "${body}")
string(REPLACE "<semicolon>" ";" scope "${scope}")
set(open "")
set(close "")
if(NAMESPACE)
  set(open "namespace ${NAMESPACE} {\n")
  set(close "} // namespace ${NAMESPACE}\n")
endif()
# Written every time (a copy only when different would leave the output older than the
# Markdown file, and make would run this again on every build).
file(WRITE ${OUTPUT} "// Generated from ${MARKDOWN}: do not edit.\n#include \"${PRELUDE}\"\n\n${open}${scope}${close}\nvoid ${FUNCTION}() {\n${body}}\n")
