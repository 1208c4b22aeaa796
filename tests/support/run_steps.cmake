# The steps of the ctest drivers that are cmake -P scripts (consumer/run.cmake, package/deb.cmake):
# run(COMMAND...) fails the test with the command's output when it exits non-zero and leaves its
# stdout in `last_output`; expect(REGEX WHAT) fails unless `last_output` matches, else prints it.
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "failed (${code}): ${ARGN}\n${out}\n${err}")
  endif()
  set(last_output "${out}" PARENT_SCOPE)
endfunction()
function(expect pattern what)
  if(NOT last_output MATCHES "${pattern}")
    message(FATAL_ERROR "${what}: expected ${pattern}, got: ${last_output}")
  endif()
  message(STATUS "${what}: ${last_output}")
endfunction()
