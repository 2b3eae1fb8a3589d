# Compiler settings shared by every target of ours (never applied to generated or third-party code).
add_library(ispars_build_flags INTERFACE)
target_compile_options(ispars_build_flags INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor
  # Determinism: the same seed gives the same roadmap on every x86-64 machine, so never fuse
  # multiply-adds differently from one build to the next.
  -ffp-contract=off)
if(ISPARS_WERROR)
  target_compile_options(ispars_build_flags INTERFACE -Werror)
endif()
if(ISPARS_SANITIZE AND ISPARS_SANITIZE_THREAD)
  message(FATAL_ERROR "ISPARS_SANITIZE and ISPARS_SANITIZE_THREAD cannot be combined")
endif()
if(ISPARS_SANITIZE_THREAD)
  target_compile_options(ispars_build_flags INTERFACE -fsanitize=thread -fno-omit-frame-pointer)
  target_link_options(ispars_build_flags INTERFACE -fsanitize=thread)
endif()
if(ISPARS_SANITIZE)
  target_compile_options(ispars_build_flags INTERFACE
    -fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer)
  target_link_options(ispars_build_flags INTERFACE -fsanitize=address,undefined)
endif()
