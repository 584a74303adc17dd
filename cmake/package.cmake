# The installed package: public headers, the exported target gdp::gdp with its CMake config
# (find_package(gdp)) and a pkg-config file (gdp.pc). Both are relocatable.
include(CMakePackageConfigHelpers)
set(GDP_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/gdp)

install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/gdp DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
  FILES_MATCHING PATTERN "*.h")
install(EXPORT gdpTargets NAMESPACE gdp:: DESTINATION ${GDP_CMAKE_DIR})
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/gdpConfig.cmake.in ${PROJECT_BINARY_DIR}/gdpConfig.cmake
  INSTALL_DESTINATION ${GDP_CMAKE_DIR})
# 0.x: a new minor version may change the API (as the SONAME says).
write_basic_package_version_file(${PROJECT_BINARY_DIR}/gdpConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/gdpConfig.cmake ${PROJECT_BINARY_DIR}/gdpConfigVersion.cmake
  DESTINATION ${GDP_CMAKE_DIR})

# A static libgdp brings what it was built with to the consumer's link line.
if(BUILD_SHARED_LIBS)
  set(GDP_PC_REQUIRES_PRIVATE "")
else()
  set(GDP_PC_REQUIRES_PRIVATE "fmt libpng libtiff-4 libjpeg OpenEXR libdeflate cfitsio wcslib healpix_cxx ompi-cxx")
endif()
file(RELATIVE_PATH GDP_PC_PREFIX ${CMAKE_INSTALL_FULL_LIBDIR}/pkgconfig ${CMAKE_INSTALL_PREFIX})
string(REGEX REPLACE "/$" "" GDP_PC_PREFIX "${GDP_PC_PREFIX}")
configure_file(${CMAKE_CURRENT_LIST_DIR}/gdp.pc.in ${PROJECT_BINARY_DIR}/gdp.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/gdp.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
