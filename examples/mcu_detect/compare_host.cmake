# Runs the mcu_detect firmware under the emulator and the host tool on the
# same frame (from the source folder) and requires the same JSON line, but
# for time_ms. -DEMULATOR=<list> -DFIRMWARE= -DHOST_DETECT= -DFRAME=
# [-DHOST_FLAGS=--inplace] (more options for the host tool)
# Without HOST_DETECT the firmware's line is printed and the test reports
# itself skipped (SKIP_REGULAR_EXPRESSION on the message below).
execute_process(COMMAND ${EMULATOR} ${FIRMWARE} RESULT_VARIABLE frc
                OUTPUT_VARIABLE fw ERROR_VARIABLE fwerr TIMEOUT 280)
message("firmware (exit ${frc}): ${fw}${fwerr}")
if(NOT frc EQUAL 0)
  message(FATAL_ERROR "mcu_detect: the firmware failed (exit ${frc})")
endif()
if(NOT HOST_DETECT)
  message(FATAL_ERROR "mcu_detect: no ACTAG_HOST_DETECT given: nothing to compare with (SKIPPED)")
endif()
execute_process(COMMAND ${HOST_DETECT} --json --min-range 0.1 --max-range 1.5 --aperture-deg 60
                        ${HOST_FLAGS} ${FRAME}
                RESULT_VARIABLE hrc OUTPUT_VARIABLE host ERROR_VARIABLE herr)
message("host     (exit ${hrc}): ${host}${herr}")
if(NOT hrc EQUAL 0)
  message(FATAL_ERROR "mcu_detect: the host tool failed (exit ${hrc})")
endif()
string(REGEX REPLACE ", \"time_ms\": [0-9.]+[}]" "}" fw_cmp "${fw}")
string(REGEX REPLACE ", \"time_ms\": [0-9.]+[}]" "}" host_cmp "${host}")
if(fw_cmp STREQUAL fw OR host_cmp STREQUAL host)
  message(FATAL_ERROR "mcu_detect: a line without time_ms (format changed?)")
endif()
if(NOT fw_cmp STREQUAL host_cmp)
  message(FATAL_ERROR "mcu_detect: the firmware's line differs from the host tool's")
endif()
string(REGEX MATCHALL "\"id\": " ids "${fw_cmp}")
list(LENGTH ids nids)
message("mcu_detect: OK: the firmware's line equals the host tool's (${nids} detections)")
