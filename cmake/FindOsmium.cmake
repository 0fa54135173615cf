# libosmium ships no CMake config; it is header-only. This finds its headers and the
# libraries its readers need (expat for XML, zlib for gzip/PBF, bz2, lz4, threads).
find_path(OSMIUM_INCLUDE_DIR osmium/version.hpp)
find_path(PROTOZERO_INCLUDE_DIR protozero/version.hpp)
find_package(EXPAT REQUIRED)
find_package(ZLIB REQUIRED)
find_package(BZip2 REQUIRED)
find_package(Threads REQUIRED)
find_library(LZ4_LIBRARY NAMES lz4)

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(Osmium REQUIRED_VARS OSMIUM_INCLUDE_DIR PROTOZERO_INCLUDE_DIR LZ4_LIBRARY)

if(Osmium_FOUND AND NOT TARGET Osmium::Osmium)
  add_library(Osmium::Osmium INTERFACE IMPORTED)
  target_include_directories(Osmium::Osmium SYSTEM INTERFACE ${OSMIUM_INCLUDE_DIR} ${PROTOZERO_INCLUDE_DIR})
  target_compile_definitions(Osmium::Osmium INTERFACE OSMIUM_WITH_LZ4)
  target_link_libraries(Osmium::Osmium INTERFACE EXPAT::EXPAT ZLIB::ZLIB BZip2::BZip2 ${LZ4_LIBRARY} Threads::Threads)
endif()
