# cmake --install BUILD --prefix P: bin/xcut, lib/libxcut_core.a, share/xcut/{scenes,report}, include/xcut/{engine,systems,
# components}/*, lib/cmake/xcut/ (find_package(xcut CONFIG) -> xcut::core). docs/example uses it.
include(CMakePackageConfigHelpers)

install(TARGETS xcut RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
if(TARGET xcut-igtl-play)
  install(TARGETS xcut-igtl-play RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()
install(TARGETS xcut_core EXPORT xcutTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
foreach(dir engine systems components)
  install(DIRECTORY ${CMAKE_SOURCE_DIR}/${dir}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/xcut/${dir}
    FILES_MATCHING PATTERN "*.h" PATTERN "*.inl")
endforeach()

set(XCUT_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/xcut)
install(EXPORT xcutTargets NAMESPACE xcut:: DESTINATION ${XCUT_CMAKE_DIR})
configure_package_config_file(${CMAKE_SOURCE_DIR}/cmake/xcutConfig.cmake.in
  ${CMAKE_BINARY_DIR}/xcutConfig.cmake INSTALL_DESTINATION ${XCUT_CMAKE_DIR})
write_basic_package_version_file(${CMAKE_BINARY_DIR}/xcutConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/xcutConfig.cmake ${CMAKE_BINARY_DIR}/xcutConfigVersion.cmake
  ${CMAKE_SOURCE_DIR}/cmake/xcutTetgen.cmake ${CMAKE_SOURCE_DIR}/cmake/xcutCholmod.cmake DESTINATION ${XCUT_CMAKE_DIR})

# What the binary and a user need beside it: the shipped scenes, and the report and plot scripts
# `xcut compare` and `xcut bench` call (looked for in <prefix>/share/xcut/report).
install(DIRECTORY ${CMAKE_SOURCE_DIR}/scenes/ DESTINATION ${CMAKE_INSTALL_DATADIR}/xcut/scenes FILES_MATCHING
  PATTERN "*.json" PATTERN "*.msh" PATTERN "*.stl" PATTERN "*.geo")
install(DIRECTORY ${CMAKE_SOURCE_DIR}/tools/report/ DESTINATION ${CMAKE_INSTALL_DATADIR}/xcut/report FILES_MATCHING PATTERN "*.py")
install(DIRECTORY ${CMAKE_SOURCE_DIR}/tools/reference/ DESTINATION ${CMAKE_INSTALL_DATADIR}/xcut/reference FILES_MATCHING PATTERN "*.py")
