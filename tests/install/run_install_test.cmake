# ctest InstalledPackage.ConsumerBuildsAndRuns (cmake -P): installs the build tree into a scratch
# prefix, checks the installed headers (exactly engine/**/*.hpp but *_internal.hpp, and the
# store's public headers; none includes Simbody, SQLite, urdfdom or tinyxml2), configures and builds
# tests/install/consumer against the prefix, and checks that the consumer's job prints the same
# tracking_nmse as the installed `armfarm job` on the same configuration (default model from
# the installed share/armfarm).
# Variables: BUILD_DIR SOURCE_DIR WORK_DIR CXX [LAUNCHER] [BUILD_TYPE] [SANITIZE]
foreach(variable BUILD_DIR SOURCE_DIR WORK_DIR CXX)
  if(NOT DEFINED ${variable})
    message(FATAL_ERROR "run_install_test.cmake: -D${variable}=... is required")
  endif()
endforeach()

function(run_checked output_variable)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE status OUTPUT_VARIABLE output ERROR_VARIABLE errors)
  if(NOT status EQUAL 0)
    string(REPLACE ";" " " command "${ARGN}")
    message(FATAL_ERROR "${command}: exit ${status}\n${output}\n${errors}")
  endif()
  set(${output_variable} "${output}" PARENT_SCOPE)
endfunction()

set(prefix ${WORK_DIR}/prefix)
file(REMOVE_RECURSE ${WORK_DIR})
run_checked(ignored ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})

# Installed headers: the engine's and the store's public ones, nothing else, no Simbody.
file(GLOB_RECURSE installed RELATIVE ${prefix}/include/armfarm ${prefix}/include/armfarm/*)
file(GLOB_RECURSE expected RELATIVE ${SOURCE_DIR} ${SOURCE_DIR}/engine/*.hpp)
list(FILTER expected EXCLUDE REGEX "_internal\\.hpp$")
list(APPEND expected results/results_store.hpp results/store_error.hpp results/job_claims.hpp results/search_store.hpp)
list(SORT installed)
list(SORT expected)
if(NOT installed STREQUAL expected)
  message(FATAL_ERROR "installed headers differ from the public ones:\n installed: ${installed}\n expected: ${expected}")
endif()
foreach(header IN LISTS installed)
  file(STRINGS ${prefix}/include/armfarm/${header} private_includes REGEX "#include.*(Simbody|SimTK|sqlite3|urdf|tinyxml)")
  if(private_includes)
    message(FATAL_ERROR "${header} includes a private dependency: ${private_includes}")
  endif()
endforeach()
foreach(file bin/armfarm share/armfarm/models/dlr_lwr3.urdf lib/cmake/armfarm/armfarmConfig.cmake)
  if(NOT EXISTS ${prefix}/${file})
    file(GLOB_RECURSE all_files RELATIVE ${prefix} ${prefix}/*)
    message(FATAL_ERROR "${file} not installed; the prefix holds ${all_files}")
  endif()
endforeach()

# The consumer project, built against the prefix only.
set(configure_options -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_CXX_COMPILER=${CXX})
if(BUILD_TYPE)
  list(APPEND configure_options -DCMAKE_BUILD_TYPE=${BUILD_TYPE})
endif()
if(LAUNCHER)
  list(APPEND configure_options -DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER})
endif()
if(SANITIZE)
  list(APPEND configure_options "-DCMAKE_CXX_FLAGS=-fsanitize=address,undefined" "-DCMAKE_EXE_LINKER_FLAGS=-fsanitize=address,undefined")
endif()
run_checked(ignored ${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/install/consumer -B ${WORK_DIR}/consumer ${configure_options})
run_checked(ignored ${CMAKE_COMMAND} --build ${WORK_DIR}/consumer -j 2)

# The same job through the installed armfarm (its default model: share/armfarm/models).
file(WRITE ${WORK_DIR}/job.json "{\"trajectory\": {\"kind\": \"sine\", \"sine\": {\"duration\": 2.0}}}\n")
run_checked(job_json ${CMAKE_COMMAND} -E env ARMFARM_DATA_DIR=${prefix}/share/armfarm
            ${prefix}/bin/armfarm job ${WORK_DIR}/job.json --json)
string(JSON expected_nmse GET "${job_json}" metrics tracking_nmse)
run_checked(consumer_output ${WORK_DIR}/consumer/consumer ${SOURCE_DIR}/models/dlr_lwr3.urdf ${expected_nmse})
message(STATUS "consumer: ${consumer_output}armfarm job: tracking_nmse ${expected_nmse}")
run_checked(store_output ${WORK_DIR}/consumer/store_check ${WORK_DIR}/check.db)
message(STATUS "store_check: ${store_output}")
file(REMOVE_RECURSE ${WORK_DIR})
