# 3D Slicer 5.0.3's MRML library (what Slicer itself reads and writes .mrml/.mrb with) as a
# test-only oracle: Build/CMakeLists.txt builds it from ROBOPLAN_ORACLES_DIR/slicer-mrml-5.0.3 (a
# patched copy in this build tree; the shared folder stays untouched), with the project's compiler
# launcher and sanitizer, together with the oracle program rpSlicerMrmlOracle. Nothing of it is
# installed, shipped or copied into the project. Without the oracle folder the tests that need it
# skip and name the missing path.
#
# Defines: ROBOPLAN_SLICER_MRML (ON/OFF), ROBOPLAN_SLICER_MRML_SOURCE (the folder),
#          ROBOPLAN_SLICER_MRML_ORACLE (the oracle program's path), target rpSlicerMRMLBuild.
set(ROBOPLAN_SLICER_MRML_SOURCE "${ROBOPLAN_ORACLES_DIR}/slicer-mrml-5.0.3")
set(slicer_mrml_dir ${CMAKE_BINARY_DIR}/Testing/Oracles/slicer-mrml-5.0.3)
set(ROBOPLAN_SLICER_MRML_ORACLE ${slicer_mrml_dir}/bin/rpSlicerMrmlOracle)
set(ROBOPLAN_SLICER_MRML OFF)
if(NOT EXISTS "${ROBOPLAN_SLICER_MRML_SOURCE}/Libs/MRML/Core/CMakeLists.txt")
  message(STATUS "Slicer MRML oracle: ${ROBOPLAN_SLICER_MRML_SOURCE} not found; the slicer tests will skip")
  return()
endif()
set(ROBOPLAN_SLICER_MRML ON)

include(ExternalProject)
set(slicer_mrml_flags "-g0")
if(ROBOPLAN_SANITIZER_FLAGS)  # the same sanitizers as our code (RoboPlanMacros.cmake)
  list(JOIN ROBOPLAN_SANITIZER_FLAGS " " sanitizer_flags)
  string(APPEND slicer_mrml_flags " ${sanitizer_flags}")
endif()
set(slicer_mrml_program ${CMAKE_CURRENT_LIST_DIR}/rpSlicerMrmlOracle.cxx)
ExternalProject_Add(rpSlicerMRMLBuild
  SOURCE_DIR ${CMAKE_CURRENT_LIST_DIR}/Build
  BINARY_DIR ${slicer_mrml_dir}
  PREFIX ${slicer_mrml_dir}/ep
  CMAKE_GENERATOR ${CMAKE_GENERATOR}
  CMAKE_ARGS
    -DCMAKE_BUILD_TYPE=Release
    -DCMAKE_C_COMPILER=${CMAKE_C_COMPILER} -DCMAKE_CXX_COMPILER=${CMAKE_CXX_COMPILER}
    ${ROBOPLAN_SUBBUILD_CMAKE_ARGS}  # ccache and the fast linker
    "-DCMAKE_C_FLAGS=${slicer_mrml_flags}" "-DCMAKE_CXX_FLAGS=${slicer_mrml_flags}"
    -DSLICER_MRML_ORACLE_DIR=${ROBOPLAN_SLICER_MRML_SOURCE}
    -DRP_ORACLE_PROGRAM_SOURCE=${slicer_mrml_program}
  # The sub-build re-runs (a no-op for Ninja when nothing changed) so that edits of the oracle
  # program rebuild it; the libraries stay built.
  BUILD_ALWAYS ON
  INSTALL_COMMAND ""
  BUILD_BYPRODUCTS ${ROBOPLAN_SLICER_MRML_ORACLE}
  LOG_CONFIGURE ON LOG_BUILD ON LOG_OUTPUT_ON_FAILURE ON)
ExternalProject_Add_StepDependencies(rpSlicerMRMLBuild configure ${CMAKE_CURRENT_LIST_DIR}/Build/CMakeLists.txt)
