# The bytes each particle of SET takes, as partc --explain says and as the
# generated program's arrays hold them (its summary): the same number.
#
#   cmake -DPARTC=... -DPART=model.part -DPROGRAM=... -DSET=P -P check_bytes.cmake
execute_process(COMMAND ${PARTC} ${PART} --explain OUTPUT_VARIABLE explained RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "partc --explain ${PART} failed")
endif()
if(NOT explained MATCHES "\n  ${SET}: ([0-9]+) bytes per particle \\(([^)]*)\\)")
  message(FATAL_ERROR "--explain gives no bytes per particle of ${SET}:\n${explained}")
endif()
set(said ${CMAKE_MATCH_1})
set(parts "${CMAKE_MATCH_2}")
execute_process(COMMAND ${PROGRAM} --steps 0 OUTPUT_VARIABLE summary RESULT_VARIABLE status)
if(NOT status EQUAL 0 OR NOT summary MATCHES "\n${SET}: [0-9]+ particles?, ([0-9]+) bytes each")
  message(FATAL_ERROR "${PROGRAM} --steps 0 (status ${status}) gives no bytes of ${SET}:\n${summary}")
endif()
if(NOT said EQUAL CMAKE_MATCH_1)
  message(FATAL_ERROR "--explain says ${said} bytes per particle of ${SET} (${parts}); "
                      "the program stores ${CMAKE_MATCH_1}")
endif()
message(STATUS "${SET}: ${said} bytes per particle (${parts}), as stored")
