# For the scripts that run a generated program several times (-P scripts
# given -DPROGRAM and -DDIR): a fresh DIR, and run(ARGS...), which runs
# PROGRAM --quiet ARGS and stops the test when it fails.
file(REMOVE_RECURSE ${DIR})
file(MAKE_DIRECTORY ${DIR})
function(run)
  execute_process(COMMAND ${PROGRAM} --quiet ${ARGN} RESULT_VARIABLE status)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "${PROGRAM} ${ARGN} exited with ${status}")
  endif()
endfunction()
