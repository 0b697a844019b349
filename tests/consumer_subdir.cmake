# CTest script (cmake -P): a parent project (tests/consumer_subdir) that builds fairspline with
# add_subdirectory, configured, built and run; checks that fairspline behaves as a subproject:
#   - the parent's build type stands: an empty one stays empty (fairspline sets its default
#     Release only as the top-level project), a given one (Debug) is used for fairspline too;
#   - nothing but the library is built by default (no tests, benchmarks, Python module, command);
#   - -ffp-contract=off stays a private flag of the library: the consumer's own compile commands
#     do not get it (compile_commands.json), while the library's sources still do.
#   -DFAIRSPLINE_SOURCE_DIR=<fairspline source tree>   -DSOURCE_DIR=<tests/consumer_subdir>
#   -DWORK_DIR=<scratch dir>
#   optional: -DGENERATOR=<cmake generator> -DCXX_COMPILER=<path> -DCXX_FLAGS=<flags>
#             -DLINKER_FLAGS=<flags> (as in consumer.cmake)
cmake_minimum_required(VERSION 3.20)

foreach(var FAIRSPLINE_SOURCE_DIR SOURCE_DIR WORK_DIR)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "consumer_subdir.cmake: -D${var}=... is required")
  endif()
endforeach()

set(build ${WORK_DIR}/build)
file(REMOVE_RECURSE ${build})

function(run_step what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "consumer_subdir: ${what} failed (${rc}):\n${out}\n${err}")
  endif()
  set(step_output "${out}" PARENT_SCOPE)
endfunction()

function(cache_value name out)
  file(STRINGS ${build}/CMakeCache.txt line REGEX "^${name}:")
  string(REGEX REPLACE "^${name}:[A-Z]+=" "" value "${line}")
  set(${out} "${value}" PARENT_SCOPE)
endfunction()

set(configure_args -S ${SOURCE_DIR} -B ${build} -DFAIRSPLINE_SOURCE_DIR=${FAIRSPLINE_SOURCE_DIR}
    -DCMAKE_EXPORT_COMPILE_COMMANDS=ON)
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

# 1. No build type: fairspline must not force its Release default onto the parent.
run_step("configuring the parent without a build type" ${CMAKE_COMMAND} ${configure_args})
cache_value(CMAKE_CONFIGURATION_TYPES config_types)
set(multi_config OFF)
if(config_types)
  set(multi_config ON)
else()
  cache_value(CMAKE_BUILD_TYPE build_type)
  if(NOT build_type STREQUAL "")
    message(FATAL_ERROR "consumer_subdir: the parent had no build type, fairspline set "
                        "CMAKE_BUILD_TYPE to '${build_type}'")
  endif()
endif()
foreach(option TESTS BENCH CLI PYTHON)
  cache_value(FAIRSPLINE_BUILD_${option} value)
  if(value)
    message(FATAL_ERROR "consumer_subdir: FAIRSPLINE_BUILD_${option} is '${value}' in a parent")
  endif()
endforeach()

# 2. The parent's build type Debug: kept, and used for fairspline's sources as well.
run_step("configuring the parent with CMAKE_BUILD_TYPE=Debug"
         ${CMAKE_COMMAND} ${configure_args} -DCMAKE_BUILD_TYPE=Debug)
if(NOT multi_config)
  cache_value(CMAKE_BUILD_TYPE build_type)
  if(NOT build_type STREQUAL "Debug")
    message(FATAL_ERROR "consumer_subdir: the parent asked for Debug, the cache has '${build_type}'")
  endif()
endif()

# Compile flags (compile_commands.json is written at configure time): the consumer's main.cpp
# has no -ffp-contract, fairspline's sources have it (GCC/Clang) and the parent's Debug flags
# (-g, never Release's -O3 -DNDEBUG).
if(NOT EXISTS ${build}/compile_commands.json)
  message(FATAL_ERROR "consumer_subdir: no compile_commands.json (generator ${GENERATOR}); "
                      "this check needs a Makefile or Ninja generator")
endif()
file(GLOB compiler_files ${build}/CMakeFiles/*/CMakeCXXCompiler.cmake)
list(GET compiler_files 0 compiler_file)
file(STRINGS ${compiler_file} id_line REGEX "^set\\(CMAKE_CXX_COMPILER_ID ")
string(REGEX REPLACE "^set\\(CMAKE_CXX_COMPILER_ID \"([^\"]*)\"\\).*" "\\1" compiler_id "${id_line}")
file(READ ${build}/compile_commands.json commands)
string(JSON count LENGTH "${commands}")
math(EXPR last "${count} - 1")
set(consumer_seen OFF)
set(library_seen 0)
foreach(i RANGE ${last})
  string(JSON file GET "${commands}" ${i} file)
  string(JSON command GET "${commands}" ${i} command)
  if(file MATCHES "/consumer/main\\.cpp$")
    set(consumer_seen ON)
    if(command MATCHES "ffp-contract")
      message(FATAL_ERROR "consumer_subdir: -ffp-contract leaked into the consumer: ${command}")
    endif()
  elseif(file MATCHES "/src/.*\\.cpp$")
    math(EXPR library_seen "${library_seen} + 1")
    if(command MATCHES "-O3" OR command MATCHES "-DNDEBUG" OR
       (compiler_id MATCHES "^(GNU|Clang|AppleClang|IntelLLVM)$" AND NOT command MATCHES " -g "))
      message(FATAL_ERROR "consumer_subdir: fairspline compiled with Release flags in a Debug "
                          "parent: ${command}")
    endif()
    if(compiler_id MATCHES "^(GNU|Clang|AppleClang|IntelLLVM)$" AND
       NOT command MATCHES " -ffp-contract=off")
      message(FATAL_ERROR "consumer_subdir: the library lost its private -ffp-contract=off: "
                          "${command}")
    endif()
  endif()
endforeach()
if(NOT consumer_seen OR library_seen EQUAL 0)
  message(FATAL_ERROR "consumer_subdir: compile_commands.json lacks the consumer or the library")
endif()

# Built in the first configuration (no build type: no -O, no -g), which compiles in a fifth
# less time than Debug's -g; the build types' flags were checked above.
if(NOT multi_config)
  run_step("configuring the parent again without a build type"
           ${CMAKE_COMMAND} ${configure_args} -DCMAKE_BUILD_TYPE=)
endif()
run_step("building the parent" ${CMAKE_COMMAND} --build ${build} --config Debug --parallel 2)

# Only the library and the consumer were built: no program or module of fairspline's own.
file(GLOB_RECURSE built LIST_DIRECTORIES false RELATIVE ${build} ${build}/*)
list(FILTER built EXCLUDE REGEX "(^|/)CMakeFiles/")
list(FILTER built INCLUDE REGEX
     "(^|/)(fairspline|fairspline_tests|fairspline_bench|fairspline_stress|fairspline_load_test|fuzz_[a-z]+_replay)(\\.exe)?$|(^|/)_core\\..*(\\.so|\\.pyd)$")
if(built)
  message(FATAL_ERROR "consumer_subdir: fairspline built its own programs in a parent: ${built}")
endif()

set(exe ${build}/consumer)
if(EXISTS ${build}/Debug/consumer${CMAKE_EXECUTABLE_SUFFIX})
  set(exe ${build}/Debug/consumer)
endif()
run_step("running the consumer" ${exe})
if(NOT step_output MATCHES "^segments: 6\n$")
  message(FATAL_ERROR "consumer_subdir: expected 'segments: 6' (7 points, open), got "
                      "'${step_output}'")
endif()
message(STATUS "consumer_subdir: add_subdirectory(fairspline), ${library_seen} library "
               "sources, no -ffp-contract in the consumer: ${step_output}")
