# Runs one test and compares what it printed with the expected output.
#   MODE=deallog: COMMAND ARGUMENT must exit 0; its stdout is compared with numdiff.
#   MODE=error:   COMMAND ARGUMENT must exit non-zero; "exit code != 0" plus its stderr
#                 is compared exactly (the message is part of the interface); under a
#                 LAUNCHER only its lines that start with "softface:".
#   SCRATCH (optional): WORKING_DIRECTORY is copied there and the test runs in
#                 the copy, so that whatever it writes stays in the build tree.
#   LAUNCHER (optional): words separated by | run before COMMAND, e.g.
#                 "mpiexec|-n|2" (a ; list would be split by add_test).
string(REPLACE "|" ";" LAUNCHER "${LAUNCHER}")
if(SCRATCH)
  file(REMOVE_RECURSE ${SCRATCH})
  file(COPY ${WORKING_DIRECTORY}/ DESTINATION ${SCRATCH})
  set(WORKING_DIRECTORY ${SCRATCH})
endif()
execute_process(COMMAND ${LAUNCHER} ${COMMAND} ${ARGUMENT}
  WORKING_DIRECTORY ${WORKING_DIRECTORY}
  OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE rc)

if(MODE STREQUAL "deallog")
  file(WRITE ${RESULT} "${out}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "test exited with ${rc}\n--- stdout:\n${out}\n--- stderr:\n${err}")
  endif()
  if(NUMDIFF)
    execute_process(COMMAND ${NUMDIFF} -q -a 1e-10 -r 1e-8 -s " \t\n:=,()[]" ${EXPECTED} ${RESULT}
      RESULT_VARIABLE diff_rc)
  else()
    execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${EXPECTED} ${RESULT}
      RESULT_VARIABLE diff_rc)
  endif()
else()
  if(LAUNCHER)
    # Under mpiexec: softface's own lines; the launcher's banners about an
    # aborted job vary from run to run.
    # (A ; in a message would split CMake's list: kept as a placeholder.)
    string(REPLACE ";" "<semicolon>" err "${err}")
    string(REGEX MATCHALL "(^|\n)softface:[^\n]*" lines "${err}")
    string(REPLACE ";" "" err "${lines}")
    string(REGEX REPLACE "^\n" "" err "${err}")
    string(REPLACE "<semicolon>" ";" err "${err}")
    if(NOT err STREQUAL "")
      string(APPEND err "\n")
    endif()
  endif()
  if(rc EQUAL 0)
    file(WRITE ${RESULT} "exit code 0\n${err}")
  else()
    file(WRITE ${RESULT} "exit code != 0\n${err}")
  endif()
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${EXPECTED} ${RESULT}
    RESULT_VARIABLE diff_rc)
endif()

if(NOT diff_rc EQUAL 0)
  execute_process(COMMAND diff ${EXPECTED} ${RESULT} OUTPUT_VARIABLE d)
  message(FATAL_ERROR "output differs from ${EXPECTED}:\n${d}")
endif()
