# CTest script (cmake -P): install the built project into a temporary prefix, then configure,
# build and run tests/consumer against it with find_package(fairspline).
#   -DBUILD_DIR=<fairspline build dir>   -DSOURCE_DIR=<tests/consumer>   -DWORK_DIR=<scratch dir>
#   optional: -DCONFIG=<build config> -DGENERATOR=<cmake generator> -DCXX_COMPILER=<path>
#             -DCXX_FLAGS=<flags> -DLINKER_FLAGS=<flags> (e.g. sanitizers: the consumer must link
#             the installed static library with the flags it was built with)
cmake_minimum_required(VERSION 3.20)

foreach(var BUILD_DIR SOURCE_DIR WORK_DIR)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "consumer.cmake: -D${var}=... is required")
  endif()
endforeach()
if(NOT CONFIG)
  set(CONFIG Release)
endif()

set(prefix ${WORK_DIR}/prefix)
set(consumer_build ${WORK_DIR}/build)
file(REMOVE_RECURSE ${prefix} ${consumer_build})

function(run_step what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "consumer: ${what} failed (${rc}):\n${out}\n${err}")
  endif()
  set(step_output "${out}" PARENT_SCOPE)
endfunction()

run_step("install into ${prefix}"
         ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix} --config ${CONFIG})
if(NOT EXISTS ${prefix}/include/fairspline/fairspline.hpp)
  message(FATAL_ERROR "consumer: the install did not put fairspline.hpp under ${prefix}/include")
endif()

set(configure_args -S ${SOURCE_DIR} -B ${consumer_build} -DCMAKE_PREFIX_PATH=${prefix}
    -DCMAKE_BUILD_TYPE=${CONFIG} -DCMAKE_FIND_PACKAGE_PREFER_CONFIG=ON)
if(GENERATOR)
  list(APPEND configure_args -G ${GENERATOR})
endif()
if(CXX_COMPILER)
  list(APPEND configure_args -DCMAKE_CXX_COMPILER=${CXX_COMPILER})
endif()
if(CXX_FLAGS)
  list(APPEND configure_args "-DCMAKE_CXX_FLAGS=${CXX_FLAGS}")
endif()
if(LINKER_FLAGS)
  list(APPEND configure_args "-DCMAKE_EXE_LINKER_FLAGS=${LINKER_FLAGS}")
endif()
run_step("configuring the consumer" ${CMAKE_COMMAND} ${configure_args})
# find_package must have used the freshly installed config, not another fairspline.
file(STRINGS ${consumer_build}/CMakeCache.txt dir_line REGEX "^fairspline_DIR:")
string(REGEX REPLACE "^fairspline_DIR:[A-Z]+=" "" found_dir "${dir_line}")
file(REAL_PATH "${found_dir}" found_dir)
file(REAL_PATH "${prefix}" real_prefix)
string(FIND "${found_dir}" "${real_prefix}/" at)
if(NOT at EQUAL 0)
  message(FATAL_ERROR "consumer: find_package(fairspline) used ${found_dir}, not ${prefix}")
endif()

run_step("building the consumer" ${CMAKE_COMMAND} --build ${consumer_build} --config ${CONFIG})

set(exe ${consumer_build}/consumer)
if(EXISTS ${consumer_build}/${CONFIG}/consumer${CMAKE_EXECUTABLE_SUFFIX})
  set(exe ${consumer_build}/${CONFIG}/consumer)
endif()
run_step("running the consumer" ${exe})
if(NOT step_output MATCHES "^segments: 6\n$")
  message(FATAL_ERROR "consumer: expected 'segments: 6' (7 points, open), got '${step_output}'")
endif()
message(STATUS "consumer: find_package(fairspline) from ${found_dir}: ${step_output}")
