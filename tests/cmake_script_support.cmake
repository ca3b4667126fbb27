# What the CMake test scripts (run with cmake -P) share: their required -D variables, the
# default configuration, and running one step that must succeed.

# Fails unless every named variable was given with -D.
function(require_script_variables script)
  foreach(v ${ARGN})
    if(NOT DEFINED ${v})
      message(FATAL_ERROR "${script}: -D${v}=... is required")
    endif()
  endforeach()
endfunction()

if(NOT CONFIG)
  set(CONFIG Release)
endif()

# Runs the command; prints its output, and fails naming `what` if it exits non-zero.
function(run_step what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message("${out}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}):\n${out}\n${err}")
  endif()
endfunction()
