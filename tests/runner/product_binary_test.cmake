# The product armfarm contains no test double: no symbol of the fake job (tests/support/fake_job.hpp)
# and no name of the environment switch that once chose it. The same checks must find the fake job
# in the test binary armfarm_fakejobs, so that a check that can no longer see a symbol fails too.
# cmake -DNM=nm -DPRODUCT=path/armfarm -DTEST_BINARY=path/armfarm_fakejobs -P product_binary_test.cmake
foreach(var NM PRODUCT TEST_BINARY)
  if(NOT ${var})
    message(FATAL_ERROR "product_binary_test.cmake: -D${var}=... is required")
  endif()
endforeach()

# The number of defined symbols of `binary` whose mangled name contains `pattern`.
function(count_symbols binary pattern out)
  execute_process(COMMAND ${NM} --defined-only ${binary} OUTPUT_VARIABLE symbols RESULT_VARIABLE status)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "${NM} ${binary} failed (${status})")
  endif()
  string(REGEX MATCHALL "[^\n]*${pattern}[^\n]*" found "${symbols}")
  list(LENGTH found n)
  set(${out} ${n} PARENT_SCOPE)
endfunction()

count_symbols(${TEST_BINARY} "make_fake_job" in_test_binary)
if(in_test_binary EQUAL 0)
  message(FATAL_ERROR "no fake-job symbol in the test binary ${TEST_BINARY}: the check sees nothing")
endif()
count_symbols(${PRODUCT} "fake_job" in_product)
if(NOT in_product EQUAL 0)
  message(FATAL_ERROR "${PRODUCT} contains ${in_product} fake-job symbols (tests/support/fake_job.cpp belongs to armfarm_fakejobs only)")
endif()
file(STRINGS ${PRODUCT} switch REGEX "ARMFARM_FAKE_JOBS")
if(switch)
  message(FATAL_ERROR "${PRODUCT} contains the text ARMFARM_FAKE_JOBS: ${switch}")
endif()
message(STATUS "armfarm: 0 fake-job symbols; armfarm_fakejobs: ${in_test_binary}")
