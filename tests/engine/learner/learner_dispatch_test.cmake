# The learner-kind dispatch is closed: visit_learner with a case for every concrete learner
# compiles, and the same call without one does not (tests/data/learner_dispatch/). The first
# compile proves the command line is right, so that the second fails for the missing case alone.
# cmake -DCXX=c++ -DSOURCE_DIR=... -DINCLUDES="dir;dir" -P learner_dispatch_test.cmake
foreach(var CXX SOURCE_DIR INCLUDES)
  if(NOT ${var})
    message(FATAL_ERROR "learner_dispatch_test.cmake: -D${var}=... is required")
  endif()
endforeach()
set(fixture ${SOURCE_DIR}/tests/data/learner_dispatch/visit_every_learner.cpp)
set(flags -std=c++17 -fsyntax-only -I${SOURCE_DIR})
foreach(dir IN LISTS INCLUDES)
  list(APPEND flags -isystem ${dir})
endforeach()

execute_process(COMMAND ${CXX} ${flags} ${fixture} RESULT_VARIABLE every_case ERROR_VARIABLE every_case_errors)
if(NOT every_case EQUAL 0)
  message(FATAL_ERROR "visit_learner with every case does not compile (${every_case}):\n${every_case_errors}")
endif()
execute_process(COMMAND ${CXX} ${flags} -DARMFARM_LEAVE_OUT_A_CASE ${fixture} RESULT_VARIABLE missing_case
                ERROR_VARIABLE missing_case_errors)
if(missing_case EQUAL 0)
  message(FATAL_ERROR "visit_learner without the SsgprFittingLearner case compiled: a learner kind can go unhandled")
endif()
if(NOT missing_case_errors MATCHES "SsgprFittingLearner")
  message(FATAL_ERROR "the compile without a case failed for another reason:\n${missing_case_errors}")
endif()
