# Fails if a step the driver runs (for a fluid, a solid and a coupled problem) is not
# named in docs/architecture.md. -DMPMICE=<exe> -DSOURCE_DIR=<repo>
file(READ "${SOURCE_DIR}/docs/architecture.md" doc)
foreach(problem sod.yaml bar.yaml piston.yaml burn_box.yaml)
  execute_process(COMMAND ${MPMICE} ${SOURCE_DIR}/problems/${problem} --steps
                  RESULT_VARIABLE rc OUTPUT_VARIABLE table ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "mpmice --steps ${problem} failed: ${err}")
  endif()
  string(REGEX MATCHALL "\\| `[a-z0-9_]+` \\|" rows "${table}")
  foreach(row IN LISTS rows)
    string(REGEX REPLACE "\\| `([a-z0-9_]+)` \\|" "\\1" step "${row}")
    # In the mapping table, whose third column starts with a kernel file.
  string(FIND "${doc}" "| `${step}` | `" at)
    if(at EQUAL -1)
      message(FATAL_ERROR "step '${step}' (${problem}) is not in the step table of docs/architecture.md")
    endif()
  endforeach()
endforeach()
message(STATUS "every driver step is in docs/architecture.md")
