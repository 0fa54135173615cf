# roadcross_warnings(target): the project's warning set, applied to our own targets only
# (third-party headers are included as SYSTEM so their warnings do not drown ours).
function(roadcross_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wconversion
                                           -Wno-sign-conversion)
endfunction()
