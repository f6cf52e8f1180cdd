# Upstream OpenIGTLink 3.x (what PLUS and 3D Slicer's OpenIGTLinkIF are built on) as a test-only
# oracle: built from ROBOPLAN_ORACLES_DIR/openigtlink-3 into this build tree (static library +
# the example programs that stand in for PLUS and Slicer), with the same sanitizer as the
# project so that AddressSanitizer sees upstream's reads of our bytes. Nothing of it is
# installed, shipped or copied into the project. Without the oracle folder the tests that need
# it skip and name the missing path.
#
# Defines: ROBOPLAN_UPSTREAM_IGTL (ON/OFF), ROBOPLAN_UPSTREAM_IGTL_SOURCE (the folder),
#          ROBOPLAN_UPSTREAM_IGTL_BIN (the example programs), target rpUpstreamOpenIGTLink.
set(ROBOPLAN_UPSTREAM_IGTL_SOURCE "${ROBOPLAN_ORACLES_DIR}/openigtlink-3")
set(ROBOPLAN_UPSTREAM_IGTL OFF)
if(TARGET rpUpstreamOpenIGTLink)
  set(ROBOPLAN_UPSTREAM_IGTL ON)
  return()
endif()
if(NOT EXISTS "${ROBOPLAN_UPSTREAM_IGTL_SOURCE}/CMakeLists.txt")
  message(STATUS "OpenIGTLink oracle: ${ROBOPLAN_UPSTREAM_IGTL_SOURCE} not found; upstream tests will skip")
  return()
endif()
set(ROBOPLAN_UPSTREAM_IGTL ON)

include(ExternalProject)
set(upstream_dir ${CMAKE_BINARY_DIR}/Testing/Oracles/openigtlink-3)
set(ROBOPLAN_UPSTREAM_IGTL_BIN ${upstream_dir}/bin)
set(upstream_flags "-w -g")  # not our code: no warnings
if(ROBOPLAN_SANITIZER_FLAGS)  # the same sanitizers as our code (RoboPlanMacros.cmake)
  list(JOIN ROBOPLAN_SANITIZER_FLAGS " " sanitizer_flags)
  string(APPEND upstream_flags " ${sanitizer_flags}")
endif()
# The peers the tests run (PLUS and Slicer stand-ins); only these are built.
set(ROBOPLAN_UPSTREAM_IGTL_PROGRAMS
  TrackerServer TrackingDataServer QuaternionTrackingDataServer StatusServer ImagerServer StringServer
  ReceiveClient TrackingDataClient QuaternionTrackingDataClient)
set(upstream_byproducts ${upstream_dir}/lib/libOpenIGTLink.a)
foreach(program ${ROBOPLAN_UPSTREAM_IGTL_PROGRAMS})
  list(APPEND upstream_byproducts ${upstream_dir}/bin/${program})
endforeach()
ExternalProject_Add(rpUpstreamOpenIGTLinkBuild
  SOURCE_DIR ${ROBOPLAN_UPSTREAM_IGTL_SOURCE}
  BINARY_DIR ${upstream_dir}
  PREFIX ${upstream_dir}/ep
  CMAKE_ARGS
    -DCMAKE_BUILD_TYPE=Release
    -DCMAKE_C_COMPILER=${CMAKE_C_COMPILER} -DCMAKE_CXX_COMPILER=${CMAKE_CXX_COMPILER}
    ${ROBOPLAN_SUBBUILD_CMAKE_ARGS}  # ccache and the fast linker (RoboPlanMacros.cmake)
    "-DCMAKE_C_FLAGS=${upstream_flags}" "-DCMAKE_CXX_FLAGS=${upstream_flags}"
    -DBUILD_SHARED_LIBS=OFF -DBUILD_EXAMPLES=ON -DBUILD_TESTING=OFF -DBUILD_DOCUMENTATION=OFF
    -DOpenIGTLink_PROTOCOL_VERSION_3=ON
  BUILD_COMMAND ${CMAKE_COMMAND} --build . --target OpenIGTLink ${ROBOPLAN_UPSTREAM_IGTL_PROGRAMS}
  INSTALL_COMMAND ""
  BUILD_BYPRODUCTS ${upstream_byproducts}
  EXCLUDE_FROM_ALL ON
  LOG_CONFIGURE ON LOG_BUILD ON LOG_OUTPUT_ON_FAILURE ON)

file(MAKE_DIRECTORY ${upstream_dir})  # holds generated headers (igtlConfigure.h ...) after the build
add_library(rpUpstreamOpenIGTLink STATIC IMPORTED GLOBAL)
set_target_properties(rpUpstreamOpenIGTLink PROPERTIES
  IMPORTED_LOCATION ${upstream_dir}/lib/libOpenIGTLink.a
  INTERFACE_LINK_LIBRARIES Threads::Threads
  INTERFACE_SYSTEM_INCLUDE_DIRECTORIES
    "${ROBOPLAN_UPSTREAM_IGTL_SOURCE}/Source;${ROBOPLAN_UPSTREAM_IGTL_SOURCE}/Source/igtlutil;${upstream_dir}"
  INTERFACE_INCLUDE_DIRECTORIES
    "${ROBOPLAN_UPSTREAM_IGTL_SOURCE}/Source;${ROBOPLAN_UPSTREAM_IGTL_SOURCE}/Source/igtlutil;${upstream_dir}")
add_dependencies(rpUpstreamOpenIGTLink rpUpstreamOpenIGTLinkBuild)
set(ROBOPLAN_UPSTREAM_IGTL_BIN ${ROBOPLAN_UPSTREAM_IGTL_BIN} CACHE INTERNAL "")
