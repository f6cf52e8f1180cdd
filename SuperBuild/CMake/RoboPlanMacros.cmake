# Helpers shared by every RoboPlan target: warnings, sanitizers, tests, benchmarks, modules.

# Warnings apply to our own targets only; VTK/ITK/Qt headers come in as SYSTEM includes.
add_library(roboplan_warnings INTERFACE)
target_compile_options(roboplan_warnings INTERFACE -Wall -Wextra)

# VTK's object factories (OpenGL render window, context device, interactor style...) are
# registered by autoinit definitions, which need the implementing modules linked. Executables,
# modules and rendering libraries get all the VTK modules the project found.
function(roboplan_vtk_autoinit target)
  if(VTK_LIBRARIES)
    target_link_libraries(${target} PRIVATE ${VTK_LIBRARIES})
    vtk_module_autoinit(TARGETS ${target} MODULES ${VTK_LIBRARIES})
  endif()
endfunction()

# ROBOPLAN_LINKER: auto (mold, else lld, else the compiler's default), mold, lld, gold, bfd or
# default. A build links about 100 executables, modules and libraries
# against VTK, ITK and Qt; measured on this project: GNU ld 1.1-2.3 s a link, gold 0.3-0.5 s, lld
# 0.2-0.3 s. Sets ROBOPLAN_SUBBUILD_CMAKE_ARGS: the compiler launchers (ccache) and the linker, for
# ExternalProject sub-builds of other projects (CMAKE_ARGS ... ${ROBOPLAN_SUBBUILD_CMAKE_ARGS}).
macro(roboplan_setup_linker)
  set(ROBOPLAN_LINKER auto CACHE STRING "Linker: auto, mold, lld, gold, bfd or default")
  set_property(CACHE ROBOPLAN_LINKER PROPERTY STRINGS auto mold lld gold bfd default)
  include(CheckLinkerFlag)
  set(_candidates ${ROBOPLAN_LINKER})
  if(ROBOPLAN_LINKER STREQUAL "auto")
    set(_candidates mold lld)
  elseif(ROBOPLAN_LINKER STREQUAL "default")
    set(_candidates)
  endif()
  set(ROBOPLAN_LINKER_FLAG "")
  foreach(_linker ${_candidates})
    check_linker_flag(CXX "-fuse-ld=${_linker}" ROBOPLAN_LINKER_${_linker}_WORKS)
    if(ROBOPLAN_LINKER_${_linker}_WORKS)
      set(ROBOPLAN_LINKER_FLAG "-fuse-ld=${_linker}")
      break()
    elseif(NOT ROBOPLAN_LINKER STREQUAL "auto")
      message(FATAL_ERROR "ROBOPLAN_LINKER=${ROBOPLAN_LINKER}: the compiler cannot link with -fuse-ld=${_linker}")
    endif()
  endforeach()
  # Only the libraries a binary uses are recorded as needed: targets link VTK, ITK and DCMTK by the
  # list (every VTK module for the object factories' autoinit, all of ITK), and each library
  # recorded is mapped and relocated at every start of `roboplan` and of every module it loads.
  add_link_options(LINKER:--as-needed)
  # Our shared libraries and modules call their own functions directly, not through the dynamic
  # linker: most of their symbol relocations were vtable slots of the ITK and VTK templates they
  # instantiate, each a symbol lookup across every library loaded when a command starts
  # (libRoboPlanSegmentationToMeshLogic.so: 12 199 symbol relocations, 5 350 with this).
  foreach(_kind SHARED MODULE)
    string(APPEND CMAKE_${_kind}_LINKER_FLAGS " -Wl,-Bsymbolic-functions")
  endforeach()
  set(ROBOPLAN_SUBBUILD_CMAKE_ARGS)
  if(ROBOPLAN_LINKER_FLAG)
    add_link_options(${ROBOPLAN_LINKER_FLAG})
    foreach(_kind EXE SHARED MODULE)
      list(APPEND ROBOPLAN_SUBBUILD_CMAKE_ARGS "-DCMAKE_${_kind}_LINKER_FLAGS_INIT=${ROBOPLAN_LINKER_FLAG}")
    endforeach()
    message(STATUS "Linker: ${ROBOPLAN_LINKER_FLAG}")
  endif()
  foreach(_lang C CXX)
    if(CMAKE_${_lang}_COMPILER_LAUNCHER)
      list(APPEND ROBOPLAN_SUBBUILD_CMAKE_ARGS "-DCMAKE_${_lang}_COMPILER_LAUNCHER=${CMAKE_${_lang}_COMPILER_LAUNCHER}")
    endif()
  endforeach()
endmacro()

# ROBOPLAN_SANITIZE: address, undefined, address,undefined (both in one build) or thread. Sets
# ROBOPLAN_SANITIZER_FLAGS (also for sub-builds of other projects) and applies them to every target,
# and ROBOPLAN_SANITIZER_TEST_ENVIRONMENT and ROBOPLAN_SANITIZER_TIMEOUT_FACTOR for every test
# (roboplan_set_test_run, which roboplan_add_test calls; plain add_test() calls call it themselves).
# UBSan reports stay recoverable in the binaries so that the suppressions for third-party headers
# work (an unrecoverable report cannot be suppressed); the tests' halt_on_error=1 still stops at
# the first report that is not suppressed.
macro(roboplan_setup_sanitizer)
  set(ROBOPLAN_SANITIZER_FLAGS "")
  if(ROBOPLAN_SANITIZE STREQUAL "address")
    set(ROBOPLAN_SANITIZER_FLAGS -fsanitize=address)
  elseif(ROBOPLAN_SANITIZE STREQUAL "undefined")
    set(ROBOPLAN_SANITIZER_FLAGS -fsanitize=undefined)
  elseif(ROBOPLAN_SANITIZE STREQUAL "address,undefined" OR ROBOPLAN_SANITIZE STREQUAL "address+undefined")
    set(ROBOPLAN_SANITIZER_FLAGS -fsanitize=address,undefined)
  elseif(ROBOPLAN_SANITIZE STREQUAL "thread")
    set(ROBOPLAN_SANITIZER_FLAGS -fsanitize=thread)
  elseif(NOT ROBOPLAN_SANITIZE STREQUAL "")
    message(FATAL_ERROR "ROBOPLAN_SANITIZE must be address, undefined, address,undefined, thread or empty")
  endif()
  if(ROBOPLAN_SANITIZER_FLAGS)
    list(APPEND ROBOPLAN_SANITIZER_FLAGS -fno-omit-frame-pointer)
    add_compile_options(${ROBOPLAN_SANITIZER_FLAGS})
    add_link_options(${ROBOPLAN_SANITIZER_FLAGS})
    # Stop on the first report, stacks for UBSan, third-party noise suppressed (Testing/Support/*.supp).
    # No strict_string_checks: it reads past the length given to strndup (libxkbcommon-x11 passes
    # buffers that are not NUL-terminated, which strndup allows).
    set(_support ${PROJECT_SOURCE_DIR}/Testing/Support)
    set(ROBOPLAN_SANITIZER_TEST_ENVIRONMENT
      "ASAN_OPTIONS=detect_leaks=1:abort_on_error=0:detect_stack_use_after_return=1"
      "LSAN_OPTIONS=suppressions=${_support}/lsan.supp:print_suppressions=0"
      "UBSAN_OPTIONS=suppressions=${_support}/ubsan.supp:print_stacktrace=1:halt_on_error=1"
      "TSAN_OPTIONS=suppressions=${_support}/tsan.supp:halt_on_error=1:second_deadlock_stack=1")
    # TSan intercepts pthread create/join/mutex/condvar even inside the uninstrumented VTK and ITK,
    # but not the futex waits of TBB's scheduler or of the std::future ITK's pool hands work back
    # through, so with the default back-ends it reports their workers' writes as races with the
    # caller. Under TSan both toolkits use back-ends built on std::thread/pthread whose joins it sees:
    # ITK's PlatformMultiThreader and VTK's STDThread SMP back-end (compiled into Debian's VTK 9.1).
    if(ROBOPLAN_SANITIZE STREQUAL "thread")
      list(APPEND ROBOPLAN_SANITIZER_TEST_ENVIRONMENT
        "ITK_GLOBAL_DEFAULT_THREADER=Platform" "VTK_SMP_BACKEND_IN_USE=STDThread")
    endif()
    # GUI tests under LeakSanitizer: Mesa's GLX vendor library and its DRI driver are unloaded
    # when the display closes, before the leak check, so the driver's leaks have stacks in an
    # unknown module that lsan.supp cannot match (56-byte blocks reported from every GL test).
    # run-with-xvfb.sh preloads them (after the ASan runtime, which must come first) into the test
    # only, so they stay loaded and their frames are named.
    if(ROBOPLAN_SANITIZE MATCHES "address")
      execute_process(COMMAND ${CMAKE_CXX_COMPILER} -print-file-name=libasan.so
                      OUTPUT_VARIABLE _asan_runtime OUTPUT_STRIP_TRAILING_WHITESPACE)
      find_file(ROBOPLAN_MESA_DRI_DRIVER swrast_dri.so PATHS /usr/lib/x86_64-linux-gnu/dri /usr/lib/dri
                PATH_SUFFIXES dri NO_DEFAULT_PATH)
      find_library(ROBOPLAN_MESA_GLX_VENDOR NAMES libGLX_mesa.so.0 GLX_mesa)
      set(_preload "")
      foreach(_lib IN ITEMS ${_asan_runtime} ${ROBOPLAN_MESA_DRI_DRIVER} ${ROBOPLAN_MESA_GLX_VENDOR})
        if(EXISTS "${_lib}")
          string(APPEND _preload " ${_lib}")
        endif()
      endforeach()
      string(STRIP "${_preload}" _preload)
      list(APPEND ROBOPLAN_SANITIZER_TEST_ENVIRONMENT "ROBOPLAN_GUI_TEST_PRELOAD=${_preload}")
    endif()
  else()
    set(ROBOPLAN_SANITIZER_TEST_ENVIRONMENT "")
  endif()
  # Test timeouts are set for the plain build; TSan runs code 5-15x slower, ASan about 2x.
  if(ROBOPLAN_SANITIZE STREQUAL "thread")
    set(ROBOPLAN_SANITIZER_TIMEOUT_FACTOR 4)
  elseif(ROBOPLAN_SANITIZER_FLAGS)
    set(ROBOPLAN_SANITIZER_TIMEOUT_FACTOR 2)
  else()
    set(ROBOPLAN_SANITIZER_TIMEOUT_FACTOR 1)
  endif()
endmacro()

# The longest tests, with their seconds in a full `ctest -j2` on 2 cores (a build tree's
# Testing/Temporary/CTestCostData.txt): their COST, so that `ctest -j` starts them first. A fresh
# build tree has no cost data; ctest then started them in the order they were added, the longest
# among the last, and one core sat idle while they finished.
set(ROBOPLAN_LONG_TESTS
  rpPictureSoakTest 96  rpDemoSystemTest 71  rpCohortMemoryTest 29 
  rpWorkflow_slurm_Test 25  rpBenchmarkSmokeTest_rpGuidanceBenchmark 20  rpOpenDataArgumentTest 16
  rpBenchmarkSmokeTest_rpVolumesBenchmark 15  rpNdiDriverTest 15  rpDicomSegmentationTest 13
  rpBenchmarkChartHeadlessTest 11  rpBenchmarkSmokeTest_rpMeshWholeProcessBenchmark 11
  vtkRPTrackingLogicTest 11  rpBenchmarkSmokeTest_rpTrackingBenchmark 10  rpBoneSplitTest 10)

# roboplan_set_test_run(<test> <timeout s> [<VAR=value>...]): the test's timeout (scaled by the
# sanitizer's factor), environment (with the sanitizer's) and, for the long ones, COST: for every
# test, ours or plain add_test. The factor also reaches the tests' own waits
# (ROBOPLAN_TEST_TIME_FACTOR, Testing/Support/rpTestTime.h).
function(roboplan_set_test_run name timeout)
  math(EXPR timeout "${timeout} * ${ROBOPLAN_SANITIZER_TIMEOUT_FACTOR}")
  set_tests_properties(${name} PROPERTIES TIMEOUT ${timeout})
  list(FIND ROBOPLAN_LONG_TESTS ${name} at)
  if(at GREATER -1)
    math(EXPR at "${at} + 1")
    list(GET ROBOPLAN_LONG_TESTS ${at} seconds)
    set_tests_properties(${name} PROPERTIES COST ${seconds})
  endif()
  set(environment ${ARGN} ${ROBOPLAN_SANITIZER_TEST_ENVIRONMENT})
  if(ROBOPLAN_SANITIZER_TIMEOUT_FACTOR GREATER 1)
    list(APPEND environment "ROBOPLAN_TEST_TIME_FACTOR=${ROBOPLAN_SANITIZER_TIMEOUT_FACTOR}")
  endif()
  if(environment)
    set_tests_properties(${name} PROPERTIES ENVIRONMENT "${environment}")
  endif()
endfunction()

# roboplan_add_library(<name> [STATIC|SHARED] SOURCES ... [PUBLIC_LIBS ...] [PRIVATE_LIBS ...])
# Include directory is the calling folder.
function(roboplan_add_library name)
  cmake_parse_arguments(A "STATIC;SHARED" "" "SOURCES;PUBLIC_LIBS;PRIVATE_LIBS" ${ARGN})
  set(kind SHARED)
  if(A_STATIC)
    set(kind STATIC)
  endif()
  add_library(${name} ${kind} ${A_SOURCES})
  target_include_directories(${name} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR} ${CMAKE_CURRENT_BINARY_DIR})
  target_link_libraries(${name} PUBLIC ${A_PUBLIC_LIBS} PRIVATE roboplan_warnings ${A_PRIVATE_LIBS})
  if("${A_PUBLIC_LIBS};${A_PRIVATE_LIBS}" MATCHES "VTK::(Rendering|Charts|Views|GUISupport|Interaction)")
    roboplan_vtk_autoinit(${name})
  endif()
endfunction()

# roboplan_add_pictures(<Module> SOURCES ... LIBS ...)
# A module's pictures (offscreen VTK rendering), lib/libRoboPlan<Module>Pictures.so: its logic
# resolves the library's extern "C" entries when a command draws (rp::SiblingLibraryFunction), so
# the logic, the module and every command map no VTK rendering, chart stack or GL until then.
function(roboplan_add_pictures module)
  cmake_parse_arguments(A "" "" "SOURCES;LIBS" ${ARGN})
  set(target RoboPlan${module}Pictures)
  add_library(${target} MODULE ${A_SOURCES})
  target_link_libraries(${target} PRIVATE roboplan_warnings ${A_LIBS} RoboPlanChartsDraw)
  roboplan_vtk_autoinit(${target})
  set_target_properties(${target} PROPERTIES LIBRARY_OUTPUT_DIRECTORY ${CMAKE_LIBRARY_OUTPUT_DIRECTORY})
  add_dependencies(roboplan-plugins ${target})
endfunction()

# roboplan_add_test(<name> SOURCES ... LIBS ... LABELS unit|integration|gui|stress
#                   [TIMEOUT s] [ARGS ...] [ENVIRONMENT ...] [OWN_MAIN])
# A GoogleTest executable registered as one ctest test. Tests labelled gui run on a virtual X
# server of their own (Testing/Support/run-with-xvfb.sh: no display-number race under ctest -j).
function(roboplan_add_test name)
  if(NOT ROBOPLAN_BUILD_TESTING)
    return()
  endif()
  cmake_parse_arguments(A "OWN_MAIN" "TIMEOUT" "SOURCES;LIBS;LABELS;ARGS;ENVIRONMENT" ${ARGN})
  set(own_main)
  if(A_OWN_MAIN)
    set(own_main OWN_MAIN)
  endif()
  roboplan_add_test_executable(${name} SOURCES ${A_SOURCES} LIBS ${A_LIBS} ${own_main})
  set(xvfb)
  if("gui" IN_LIST A_LABELS)
    set(xvfb XVFB)
  endif()
  roboplan_register_test(${name} ${name} LABELS ${A_LABELS} TIMEOUT ${A_TIMEOUT} ARGS ${A_ARGS}
    ENVIRONMENT ${A_ENVIRONMENT} ${xvfb})
endfunction()

# roboplan_add_test_executable(<name> SOURCES ... LIBS ... [OWN_MAIN]): a test program, not yet a
# ctest test (roboplan_register_test registers it, once or with several argument lists).
function(roboplan_add_test_executable name)
  cmake_parse_arguments(A "OWN_MAIN" "" "SOURCES;LIBS" ${ARGN})
  add_executable(${name} ${A_SOURCES})
  set_target_properties(${name} PROPERTIES UNITY_BUILD OFF)  # one test, one source: nothing to share
  add_dependencies(${name} roboplan-plugins)  # what the libraries under test load on first use
  # Testing/Support: helpers every test may use (rpSharedData.h: skip without ../shared/data).
  target_include_directories(${name} PRIVATE ${PROJECT_SOURCE_DIR}/Testing/Support)
  target_link_libraries(${name} PRIVATE roboplan_warnings ${A_LIBS} GTest::gtest)
  # The test's own sources at -O1 after the build type's -O3 (-O2): they set up and check, the code
  # under test is in the libraries, which keep the build type's flags.
  target_compile_options(${name} PRIVATE $<$<CONFIG:Release,RelWithDebInfo>:-O1>)
  if(NOT A_OWN_MAIN)
    target_link_libraries(${name} PRIVATE GTest::gtest_main)
  endif()
  roboplan_vtk_autoinit(${name})
  target_compile_definitions(${name} PRIVATE
    ROBOPLAN_SHARED_DATA_DIR="${ROBOPLAN_SHARED_DATA_DIR}"
    ROBOPLAN_RESOURCES_DIR="${ROBOPLAN_RESOURCES_DIR}"
    ROBOPLAN_BINARY_DIR="${CMAKE_BINARY_DIR}"
    ROBOPLAN_TEST_OUTPUT_DIR="${CMAKE_BINARY_DIR}/Testing/Temporary/${name}")
endfunction()

# roboplan_register_test(<test> <executable> LABELS ... [TIMEOUT s] [ARGS ...] [ENVIRONMENT ...]
#                        [XVFB]): runs the test program as the ctest test <test> (default label
# unit, timeout 300 s); XVFB: on a virtual X server of its own (Testing/Support/run-with-xvfb.sh).
function(roboplan_register_test test executable)
  cmake_parse_arguments(A "XVFB" "TIMEOUT" "LABELS;ARGS;ENVIRONMENT" ${ARGN})
  if(NOT A_LABELS)
    set(A_LABELS unit)
  endif()
  set(cmd $<TARGET_FILE:${executable}> ${A_ARGS})
  if(A_XVFB)
    set(cmd ${PROJECT_SOURCE_DIR}/Testing/Support/run-with-xvfb.sh ${cmd})
  endif()
  add_test(NAME ${test} COMMAND ${cmd})
  if(NOT A_TIMEOUT)
    set(A_TIMEOUT 300)
  endif()
  set_tests_properties(${test} PROPERTIES LABELS "${A_LABELS}")
  roboplan_set_test_run(${test} ${A_TIMEOUT} ${A_ENVIRONMENT})
endfunction()

# roboplan_add_benchmark(<name> SOURCES ... LIBS ...)
# Google Benchmark executable in bin/. Run by hand (see README) for figures; ctest runs each only
# quick, as its smoke test (Testing/Benchmarks/CMakeLists.txt), which puts them in the default
# build when tests are on; `--target benchmarks` builds them alone.
function(roboplan_add_benchmark name)
  if(NOT ROBOPLAN_BUILD_BENCHMARKS)
    return()
  endif()
  cmake_parse_arguments(A "" "" "SOURCES;LIBS" ${ARGN})
  add_executable(${name} EXCLUDE_FROM_ALL ${A_SOURCES})
  set_target_properties(${name} PROPERTIES UNITY_BUILD OFF)
  add_dependencies(benchmarks ${name})
  add_dependencies(${name} roboplan-plugins)
  # Testing/Benchmarks/rpBenchmarkMain.h: the run's conditions in every benchmark's output.
  target_include_directories(${name} PRIVATE ${PROJECT_SOURCE_DIR}/Testing/Benchmarks)
  target_link_libraries(${name} PRIVATE roboplan_warnings ${A_LIBS} RoboPlanBenchmarkCommon benchmark::benchmark)
  roboplan_vtk_autoinit(${name})
  target_compile_definitions(${name} PRIVATE
    ROBOPLAN_SHARED_DATA_DIR="${ROBOPLAN_SHARED_DATA_DIR}"
    ROBOPLAN_RESOURCES_DIR="${ROBOPLAN_RESOURCES_DIR}")
endfunction()

# roboplan_add_module_widgets(<Name> SOURCES Widgets/qRP<Name>Panel.cxx ... LIBS <logic> ...
#                             PLUGIN Widgets/<Name>PanelPlugin.cxx)
# A module's Qt panel layer: the static library RoboPlan<Name>Widgets (headers in Widgets/, each
# .cxx's header beside it added for moc), linked into the panel's GUI test and into the panel
# plugin lib/roboplan-modules/libRoboPlanPanel<Name>.so made from PLUGIN (the file that exports
# roboplan_create_module_panel, Libs/ModuleCore/rpModule.h). The viewer loads that plugin when it
# shows the module's panel; the module's own plugin does not link Qt, so a command maps none of it.
# Does nothing when the GUI is not built.
function(roboplan_add_module_widgets name)
  if(NOT ROBOPLAN_BUILD_GUI)
    return()
  endif()
  cmake_parse_arguments(A "" "PLUGIN" "SOURCES;LIBS" ${ARGN})
  if(NOT A_PLUGIN)
    message(FATAL_ERROR "roboplan_add_module_widgets(${name}): PLUGIN Widgets/${name}PanelPlugin.cxx is missing")
  endif()
  set(target RoboPlan${name}Widgets)
  set(sources ${A_SOURCES})
  foreach(source ${A_SOURCES})
    foreach(extension h ui)
      string(REGEX REPLACE "\\.cxx$" ".${extension}" companion ${source})
      if(NOT companion STREQUAL source AND EXISTS ${CMAKE_CURRENT_SOURCE_DIR}/${companion})
        list(APPEND sources ${companion})
      endif()
    endforeach()
  endforeach()
  add_library(${target} STATIC ${sources})
  # A panel's layout is its Qt Designer file beside it (qRP<Name>Panel.ui, as Slicer keeps its
  # module panels): uic makes ui_qRP<Name>Panel.h, which the panel's header includes, so the
  # generated folder is public.
  set_target_properties(${target} PROPERTIES AUTOUIC ON)
  target_include_directories(${target} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/Widgets
    ${CMAKE_CURRENT_BINARY_DIR}/${target}_autogen/include)
  target_link_libraries(${target} PUBLIC ${A_LIBS} Qt5::Widgets PRIVATE roboplan_warnings)
  set(plugin RoboPlanPanel${name})
  add_library(${plugin} MODULE ${A_PLUGIN})
  target_link_libraries(${plugin} PRIVATE roboplan_warnings RoboPlanModuleCore ${target})
  roboplan_vtk_autoinit(${plugin})  # the panels' VTK views need the OpenGL factories
  set_target_properties(${plugin} PROPERTIES
    LIBRARY_OUTPUT_DIRECTORY ${ROBOPLAN_MODULE_OUTPUT_DIRECTORY}
    BUILD_RPATH "$ORIGIN/..;${CMAKE_BINARY_DIR}/lib"
    INSTALL_RPATH "$ORIGIN/..")
  if(NOT ROBOPLAN_MODULE_NO_INSTALL)
    install(TARGETS ${plugin} LIBRARY DESTINATION ${ROBOPLAN_MODULE_DIR_NAME})
  endif()
endfunction()

# roboplan_add_module(<Name> SOURCES ... LIBS ... [SLICER_CLI_COMMANDS <command>...])
# A run-time loadable module: a shared object lib/roboplan-modules/libRoboPlanModule<Name>.so that
# exports roboplan_create_module() (see Libs/ModuleCore/rpModule.h). Building it builds its panel
# plugin when roboplan_add_module_widgets made one (call that first). SLICER_CLI_COMMANDS: the module's commands that 3D
# Slicer lists as CLI modules (they describe themselves with --xml): each gets
# lib/roboplan-cli/roboplan-<command>, a link to roboplan (roboplanMain.cxx runs it as
# `roboplan <command>`), in the build and the install tree.
function(roboplan_add_module name)
  cmake_parse_arguments(A "" "" "SOURCES;LIBS;SLICER_CLI_COMMANDS" ${ARGN})
  foreach(command IN LISTS A_SLICER_CLI_COMMANDS)
    roboplan_add_slicer_cli_link(${command})
  endforeach()
  set(target RoboPlanModule${name})
  add_library(${target} MODULE ${A_SOURCES})
  # No VTK autoinit here: a module's plugin renders nothing itself, and the libraries that render
  # bring their own (roboplan_add_library); every VTK module here would be loaded by every command.
  target_link_libraries(${target} PRIVATE roboplan_warnings RoboPlanModuleCore ${A_LIBS})
  if(TARGET RoboPlanPanel${name})
    add_dependencies(${target} RoboPlanPanel${name})
  endif()
  set_target_properties(${target} PROPERTIES
    LIBRARY_OUTPUT_DIRECTORY ${ROBOPLAN_MODULE_OUTPUT_DIRECTORY}
    BUILD_RPATH "$ORIGIN/..;${CMAKE_BINARY_DIR}/lib"
    INSTALL_RPATH "$ORIGIN/..")
  # Its manifest beside it (<library>.json, Libs/ModuleCore/rpModuleManager.h), written from the
  # module after each link: `roboplan <command>` then loads only the module that owns the command
  # (a module without a manifest that matches it is loaded at start-up). The tool loads the
  # module: no leak report from a sanitizer's exit check.
  add_dependencies(${target} roboplan-module-manifest roboplan-plugins)
  set(manifest_tool ${CMAKE_COMMAND} -E env ASAN_OPTIONS=detect_leaks=0 $<TARGET_FILE:roboplan-module-manifest>)
  add_custom_command(TARGET ${target} POST_BUILD COMMAND ${manifest_tool} $<TARGET_FILE:${target}> VERBATIM)
  if(NOT ROBOPLAN_MODULE_NO_INSTALL)  # set by Utilities/CMakeLists.txt for the template's check
    install(TARGETS ${target} LIBRARY DESTINATION ${ROBOPLAN_MODULE_DIR_NAME})
  endif()
  set_property(GLOBAL APPEND PROPERTY ROBOPLAN_MODULE_TARGETS ${target})
endfunction()

# roboplan_add_slicer_cli_link(<command>): lib/roboplan-cli/roboplan-<command> -> ../../bin/roboplan
# (made at configure time: the link may dangle until roboplan is built), and the same when installed.
function(roboplan_add_slicer_cli_link command)
  file(MAKE_DIRECTORY ${CMAKE_BINARY_DIR}/lib/roboplan-cli)
  file(CREATE_LINK ../../bin/roboplan ${CMAKE_BINARY_DIR}/lib/roboplan-cli/roboplan-${command} SYMBOLIC)
  install(CODE "file(MAKE_DIRECTORY \"\$ENV{DESTDIR}\${CMAKE_INSTALL_PREFIX}/lib/roboplan-cli\")
    file(CREATE_LINK ../../bin/roboplan \"\$ENV{DESTDIR}\${CMAKE_INSTALL_PREFIX}/lib/roboplan-cli/roboplan-${command}\" SYMBOLIC)")
endfunction()
