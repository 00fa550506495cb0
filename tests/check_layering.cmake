# Fails if a lower module includes a higher one, multibody includes deal.II, or a module
# below apps includes VTK (vtk*.h).
set(bad "")
foreach(pair "fem;coupling/" "fem;multibody/" "fem;apps/" "coupling;multibody/" "coupling;apps/"
             "multibody;apps/" "multibody;deal.II/" "multibody;fem/" "fem;vtk" "coupling;vtk"
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
# The contact solver (plantar_contact) is used by multibody, so it must not see deal.II either.
file(GLOB contact_files ${ROOT}/coupling/contact/*.h ${ROOT}/coupling/contact/*.cc)
foreach(f ${contact_files})
  file(STRINGS ${f} lines REGEX "^#include [<\"](deal.II|fem)/")
  if(lines)
    string(APPEND bad "${f}: ${lines}\n")
  endif()
endforeach()
if(bad)
  message(FATAL_ERROR "layering violations:\n${bad}")
endif()
message(STATUS "layering ok")
