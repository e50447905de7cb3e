# Installs the headers and a relocatable package configuration so that
# find_package(restir CONFIG) provides restir::restir.
include(CMakePackageConfigHelpers)

set(RESTIR_CONFIG_DIR ${CMAKE_INSTALL_DATADIR}/cmake/restir)

install(TARGETS restir EXPORT restirTargets)
install(DIRECTORY include/restir DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT restirTargets NAMESPACE restir:: DESTINATION ${RESTIR_CONFIG_DIR})

configure_package_config_file(cmake/restirConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/restirConfig.cmake
                              INSTALL_DESTINATION ${RESTIR_CONFIG_DIR})
# A header-only library does not depend on the consumer's architecture.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/restirConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion ARCH_INDEPENDENT)
install(FILES ${PROJECT_BINARY_DIR}/restirConfig.cmake
              ${PROJECT_BINARY_DIR}/restirConfigVersion.cmake
        DESTINATION ${RESTIR_CONFIG_DIR})
install(FILES LICENSE DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/restir)
