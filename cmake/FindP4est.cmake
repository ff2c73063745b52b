# FindP4est: p4est and its companion library sc (Debian: libp4est-dev),
# found by path: neither ships a CMake package or a pkg-config file.
#
#   P4est::p4est   imported target (links P4est::sc)
#   P4est::sc      imported target
#   P4est_FOUND, P4EST_INCLUDE_DIR, P4EST_LIB, SC_LIB
#
# Debian's p4est is built with MPI: a program that compiles against the
# p4est headers also needs MPI's (vorocrust's library does; its users do not).
find_path(P4EST_INCLUDE_DIR p8est_extended.h)
find_library(P4EST_LIB NAMES p4est)
find_library(SC_LIB NAMES sc)

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(P4est REQUIRED_VARS P4EST_LIB SC_LIB P4EST_INCLUDE_DIR)
mark_as_advanced(P4EST_INCLUDE_DIR P4EST_LIB SC_LIB)

if(P4est_FOUND AND NOT TARGET P4est::sc)
  add_library(P4est::sc UNKNOWN IMPORTED)
  set_target_properties(P4est::sc PROPERTIES
    IMPORTED_LOCATION "${SC_LIB}"
    INTERFACE_INCLUDE_DIRECTORIES "${P4EST_INCLUDE_DIR}")
  add_library(P4est::p4est UNKNOWN IMPORTED)
  set_target_properties(P4est::p4est PROPERTIES
    IMPORTED_LOCATION "${P4EST_LIB}"
    INTERFACE_INCLUDE_DIRECTORIES "${P4EST_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES P4est::sc)
endif()
