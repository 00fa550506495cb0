# Fails if a module includes a module above it. The floors (docs/design.md):
#   fem, contact        ground floors: fem uses deal.II; contact is Eigen only
#   coupling            a deformable pad on its contact nodes: uses fem and contact
#   multibody           Eigen + urdfdom; uses contact only (no deal.II, no fem, no coupling)
#   apps                everything (and VTK, which no module below apps uses)
set(bad "")
foreach(pair "fem;contact/" "fem;coupling/" "fem;multibody/" "fem;apps/" "contact;fem/"
             "contact;coupling/" "contact;multibody/" "contact;apps/" "contact;deal.II/"
             "coupling;multibody/" "coupling;apps/" "multibody;apps/" "multibody;deal.II/"
             "multibody;fem/" "multibody;coupling/" "fem;vtk" "contact;vtk" "coupling;vtk"
             "multibody;vtk")
  list(GET pair 0 dir)
  list(GET pair 1 forbidden)
  file(GLOB_RECURSE files ${ROOT}/${dir}/*.h ${ROOT}/${dir}/*.cc)
  foreach(f ${files})
    file(STRINGS ${f} lines REGEX "^#include [<\"]${forbidden}")
    if(lines)
      string(APPEND bad "${f}: ${lines}\n")
    endif()
  endforeach()
endforeach()
# The folders and namespaces agree: plantar::<folder> (apps: plantar::app).
foreach(dir fem contact coupling multibody)
  file(GLOB_RECURSE files ${ROOT}/${dir}/*.h)
  foreach(f ${files})
    file(STRINGS ${f} lines REGEX "^namespace plantar::")
    foreach(line ${lines})
      if(NOT line MATCHES "^namespace plantar::${dir}([ :{]|$)" AND NOT line MATCHES
                                                                    "^namespace plantar::walking")
        string(APPEND bad "${f}: '${line}' is not in namespace plantar::${dir}\n")
      endif()
    endforeach()
  endforeach()
endforeach()
if(bad)
  message(FATAL_ERROR "layering violations:\n${bad}")
endif()
message(STATUS "layering ok")
