# Runs a command and checks its exit status and what it printed.
#
#   cmake "-DCOMMAND=prog;arg;..." -DEXIT=2 "-DEXPECT=regex" [-DNO_FILE=path]
#         -P check_command.cmake
#
# EXPECT is matched against stdout and stderr together. NO_FILE names a
# file that must not exist afterwards (no partial output on failure).
if(NO_FILE)
  file(REMOVE ${NO_FILE})
endif()
execute_process(COMMAND ${COMMAND} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
set(printed "${out}${err}")
if(NOT status STREQUAL "${EXIT}")
  message(FATAL_ERROR "expected exit status ${EXIT}, got ${status}; it printed:\n${printed}")
endif()
if(NOT printed MATCHES "${EXPECT}")
  message(FATAL_ERROR "output does not match '${EXPECT}'; it printed:\n${printed}")
endif()
if(NO_FILE AND EXISTS ${NO_FILE})
  message(FATAL_ERROR "${NO_FILE} was written although the command failed")
endif()
