# Builds TARGET in the build tree BINARY_DIR and passes only when the build fails with a
# deprecation error for each message of MESSAGES (a ;-list, given with | as separator): the
# deprecated names must warn in user code, and the warning must name their replacement.
execute_process(COMMAND ${CMAKE_COMMAND} --build ${BINARY_DIR} --target ${TARGET}
                RESULT_VARIABLE result OUTPUT_VARIABLE output ERROR_VARIABLE output)
if(result EQUAL 0)
  message(FATAL_ERROR "${TARGET} compiled: its deprecated names did not warn\n${output}")
endif()
string(REPLACE "|" ";" messages "${MESSAGES}")
foreach(expected IN LISTS messages)
  string(FIND "${output}" "is deprecated: ${expected}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "No deprecation error saying '${expected}':\n${output}")
  endif()
endforeach()
message(STATUS "${TARGET}: every deprecated name warned")
