# One place that sets the language level, warnings and include layout of every planemap target.

function(planemap_set_options target)
  target_compile_features(${target} PUBLIC cxx_std_17)
  set_target_properties(${target} PROPERTIES CXX_EXTENSIONS OFF)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wno-unused-parameter)
endfunction()

# planemap_add_library(NAME SOURCES ... DEPENDS ... [NO_EXPORT]): a static library planemap_<NAME>
# with its public headers under <folder>/include/planemap/<NAME>/, installed and exported as
# planemap::<NAME> (NO_EXPORT: built here only, as the command-line tool's own commands).
function(planemap_add_library name)
  cmake_parse_arguments(ARG "NO_EXPORT" "" "SOURCES;DEPENDS;PRIVATE_DEPENDS" ${ARGN})
  add_library(planemap_${name} STATIC ${ARG_SOURCES})
  add_library(planemap::${name} ALIAS planemap_${name})
  target_include_directories(planemap_${name} PUBLIC $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
                                                     $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(planemap_${name} PUBLIC ${ARG_DEPENDS} PRIVATE ${ARG_PRIVATE_DEPENDS})
  planemap_set_options(planemap_${name})
  if(NOT ARG_NO_EXPORT)
    planemap_install_library(${name})
  endif()
endfunction()

# Installs planemap_<NAME> into the planemapTargets export set (as planemap::<NAME>) and its
# headers, when the folder has any.
function(planemap_install_library name)
  set_target_properties(planemap_${name} PROPERTIES EXPORT_NAME ${name})
  install(TARGETS planemap_${name} EXPORT planemapTargets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
          INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  if(EXISTS ${CMAKE_CURRENT_SOURCE_DIR}/include)
    install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  endif()
endfunction()

# A folder whose code arrives with a later capability still states its place in the layering.
function(planemap_add_interface_library name)
  cmake_parse_arguments(ARG "" "" "DEPENDS" ${ARGN})
  add_library(planemap_${name} INTERFACE)
  add_library(planemap::${name} ALIAS planemap_${name})
  target_link_libraries(planemap_${name} INTERFACE ${ARG_DEPENDS})
  planemap_install_library(${name})
endfunction()

function(planemap_enable_sanitizers_if_requested)
  if(PLANEMAP_SANITIZE)
    add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
    add_link_options(-fsanitize=address,undefined)
  endif()
endfunction()

# Faster links with lld when it is installed.
find_program(PLANEMAP_LLD ld.lld)
if(PLANEMAP_LLD)
  add_link_options(-fuse-ld=lld)
endif()
