# `mpmice --check` prints the input with its defaults filled in, as YAML that is itself
# a valid input resolving to the same configuration. -DMPMICE=<exe> -DSOURCE_DIR=<repo>
# -DWORK_DIR=<scratch>
file(MAKE_DIRECTORY "${WORK_DIR}")
foreach(problem sod.yaml hot_blob.yaml disks.yaml piston.yaml)
  execute_process(COMMAND ${MPMICE} --check ${SOURCE_DIR}/problems/${problem}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE first ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "--check ${problem}: exit ${rc}\n${err}")
  endif()
  string(REGEX REPLACE "^# [^\n]*\n" "" first "${first}")
  file(WRITE "${WORK_DIR}/${problem}" "${first}")
  execute_process(COMMAND ${MPMICE} --check ${WORK_DIR}/${problem}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE second ERROR_VARIABLE err)
  string(REGEX REPLACE "^# [^\n]*\n" "" second "${second}")
  if(NOT rc EQUAL 0 OR NOT first STREQUAL second)
    message(FATAL_ERROR "--check of the resolved ${problem} differs or fails (${rc}):\n${err}")
  endif()
endforeach()
message(STATUS "--check round trips")
