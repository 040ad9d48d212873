# Installs the libraries (msdeform::core, ::energies, ::solvers, ::scales, ::methods
# and the umbrella msdeform::msdeform), their headers under
# include/msdeform/<folder>/, and the CMake package that makes
#   find_package(msdeform CONFIG REQUIRED)
# work from another project (docs/library.md).
include(CMakePackageConfigHelpers)

set(MSDEFORM_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/msdeform CACHE STRING
    "Where the CMake package files go, relative to the prefix")

get_property(msdeform_libraries GLOBAL PROPERTY MSDEFORM_LIBRARIES)
install(TARGETS ${msdeform_libraries} msdeform_all
        EXPORT msdeformTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
foreach(library IN LISTS msdeform_libraries)
  get_property(headers TARGET ${library} PROPERTY MSDEFORM_HEADERS)
  get_property(folder TARGET ${library} PROPERTY MSDEFORM_FOLDER)
  install(FILES ${headers} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/msdeform/${folder})
endforeach()

install(EXPORT msdeformTargets NAMESPACE msdeform:: DESTINATION ${MSDEFORM_INSTALL_CMAKEDIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/msdeformConfig.cmake.in
  ${PROJECT_BINARY_DIR}/msdeformConfig.cmake
  INSTALL_DESTINATION ${MSDEFORM_INSTALL_CMAKEDIR})
# 0.x: a minor version may change the API, so only the same minor matches.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/msdeformConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/msdeformConfig.cmake
              ${PROJECT_BINARY_DIR}/msdeformConfigVersion.cmake
        DESTINATION ${MSDEFORM_INSTALL_CMAKEDIR})
