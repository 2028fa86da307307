# Runs one fuzzer for ctest (tests/fuzz/CMakeLists.txt):
#   cmake -DFUZZER=BIN -DWORK_DIR=DIR -DSEED_DIR=DIR -DSECONDS=N -DTIMEOUT=N -DRSS_MB=N [-DDICT=F]
#         -P run_fuzzer.cmake
# libFuzzer writes the inputs it finds to the first corpus directory and only reads the others, so
# the committed seeds (SEED_DIR) stay as they are; new inputs and crash files go to WORK_DIR in the
# build tree. The test fails if the fuzzer finds anything (libFuzzer exits non-zero).
foreach(var FUZZER WORK_DIR SEED_DIR SECONDS TIMEOUT RSS_MB)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "run_fuzzer.cmake: ${var} is not set")
  endif()
endforeach()
file(MAKE_DIRECTORY ${WORK_DIR}/corpus)
set(flags -max_total_time=${SECONDS} -timeout=${TIMEOUT} -rss_limit_mb=${RSS_MB}
          -print_final_stats=1 -artifact_prefix=${WORK_DIR}/)
if(DICT)
  list(APPEND flags -dict=${DICT})
endif()
execute_process(COMMAND ${FUZZER} ${flags} ${WORK_DIR}/corpus ${SEED_DIR}
                WORKING_DIRECTORY ${WORK_DIR}
                RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "${FUZZER} failed (${status}): the input that did it is in ${WORK_DIR}/ "
                      "(crash-*, leak-*, timeout-* or oom-*); rerun it with: ${FUZZER} FILE")
endif()
