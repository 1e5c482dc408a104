# Helpers that keep every library and app target alike.

set(SMAP_WARNINGS -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor)

# smap_add_library(NAME SOURCES ... PUBLIC_DEPS ... PRIVATE_DEPS ...)
# Creates the shared library smap_<NAME> (alias smap::<NAME>, exported as smap::<NAME> in the
# installed CMake package) with headers under include/smap/<NAME>/. Shared, so that what a
# library links privately (OctoMap, Ceres, cv::dnn) stays inside it: a program built against
# the installed package never needs them.
function(smap_add_library name)
    cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
    add_library(smap_${name} SHARED ${ARG_SOURCES})
    add_library(smap::${name} ALIAS smap_${name})
    target_include_directories(smap_${name} PUBLIC
        $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
        $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
    target_link_libraries(smap_${name} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
    target_compile_options(smap_${name} PRIVATE ${SMAP_WARNINGS})
    set_target_properties(smap_${name} PROPERTIES
        POSITION_INDEPENDENT_CODE ON
        EXPORT_NAME ${name}
        VERSION ${PROJECT_VERSION}
        SOVERSION ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR}
        INSTALL_RPATH "$ORIGIN")
    install(TARGETS smap_${name} EXPORT smapTargets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
    install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include/
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endfunction()

# smap_add_app(NAME SOURCES ... DEPS ...): an executable in <build>/bin.
function(smap_add_app name)
    cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
    add_executable(${name} ${ARG_SOURCES})
    target_link_libraries(${name} PRIVATE ${ARG_DEPS})
    target_compile_options(${name} PRIVATE ${SMAP_WARNINGS})
    install(TARGETS ${name} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endfunction()
