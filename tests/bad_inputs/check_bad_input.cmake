# Run by ctest for one bad input: mpmice must exit with status 2 (an input error,
# not a crash) and its message must contain the text after "# expect:" on the
# input's first line. -DMPMICE=<exe> -DINPUT=<file> [-DEXTRA=<arg|arg|...>]
# [-DEXPECT=<text>] (for inputs without a first line to read).
if(NOT EXPECT)
  file(STRINGS "${INPUT}" first LIMIT_COUNT 1)
  string(REGEX REPLACE "^# expect: " "" EXPECT "${first}")
endif()
set(out_dir "${WORK_DIR}")
string(REPLACE "|" ";" EXTRA "${EXTRA}")
execute_process(COMMAND ${MPMICE} ${INPUT} --output-dir ${out_dir} ${EXTRA}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT EXPECT_CODE)
  set(EXPECT_CODE 2)
endif()
if(NOT rc STREQUAL "${EXPECT_CODE}")
  message(FATAL_ERROR "exit status ${rc}, expected ${EXPECT_CODE}\nstdout:\n${out}\nstderr:\n${err}")
endif()
string(FIND "${err}" "${EXPECT}" at)
if(at EQUAL -1)
  message(FATAL_ERROR "the message does not contain \"${EXPECT}\":\n${err}")
endif()
message(STATUS "exit ${EXPECT_CODE}: ${err}")
