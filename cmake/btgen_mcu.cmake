# btgen on a microcontroller: the board support of mcu/bsp/ as CMake targets.
#
# Use with the toolchain file cmake/toolchain/arm-none-eabi-cortex-m4.cmake:
#
#   include(<btgen>/cmake/btgen.cmake)       # btgen::runtime, btgen_add_mission()
#   include(<btgen>/cmake/btgen_mcu.cmake)   # btgen::bsp, btgen_mcu_image()
#   btgen_add_mission(my_mission MISSION mission.xml)
#   add_executable(firmware main.cpp leaves.cpp)
#   target_link_libraries(firmware PRIVATE my_mission btgen::bsp)
#   btgen_mcu_image(firmware)                # `firmware.elf`, its size, `run-firmware`
#
# btgen::bsp  the board: ARM MPS2+ with the AN386 image (Cortex-M4), the
#             board QEMU emulates as `-M mps2-an386` (mcu/README.md says why
#             this one): vector table and reset handler (startup.c), UART0
#             output, the SysTick millisecond clock, semihosting exit, a
#             painted stack, and an _sbrk that stops any heap allocation
#             (bsp.cpp, syscalls.cpp), and the linker script. An object
#             library, so the vector table is always linked.
#
# What needs an operating system is not built here: btgen::scenario (reads
# files, allocates; btgen/harness/static_scenario.hpp is its heap-free
# counterpart), btgen::btlog, btgen::groot2 and btgen/async_call.hpp (threads,
# sockets). The headers of the last three stop the build under BTGEN_BARE_METAL.

include_guard(GLOBAL)

get_filename_component(_btgen_mcu_root "${CMAKE_CURRENT_LIST_DIR}/.." ABSOLUTE)

set(BTGEN_QEMU qemu-system-arm CACHE STRING "QEMU for Arm (Debian: qemu-system-arm), to run the images")
set(BTGEN_QEMU_MACHINE mps2-an386 CACHE STRING "the QEMU machine the board support is written for")

if(NOT TARGET btgen_bsp)
  set(_bsp "${_btgen_mcu_root}/mcu/bsp/mps2_an386")
  add_library(btgen_bsp OBJECT "${_bsp}/src/startup.c" "${_bsp}/src/bsp.cpp" "${_bsp}/src/syscalls.cpp")
  add_library(btgen::bsp ALIAS btgen_bsp)
  target_include_directories(btgen_bsp PUBLIC "${_bsp}/include")
  target_compile_features(btgen_bsp PUBLIC cxx_std_17)
  target_link_options(btgen_bsp INTERFACE "-T${_bsp}/mps2_an386.ld")
  set_property(TARGET btgen_bsp APPEND PROPERTY INTERFACE_LINK_DEPENDS "${_bsp}/mps2_an386.ld")
endif()

# btgen_mcu_image(<target>): after the link, print the image's sizes (text,
# data, bss) and add a `run-<target>` target that runs it in QEMU, its UART on
# the terminal, QEMU's exit status the program's.
function(btgen_mcu_image target)
  if(CMAKE_SIZE)
    add_custom_command(TARGET ${target} POST_BUILD COMMAND ${CMAKE_SIZE} "$<TARGET_FILE:${target}>" VERBATIM)
  endif()
  add_custom_target(run-${target}
    COMMAND ${BTGEN_QEMU} -M ${BTGEN_QEMU_MACHINE} -display none -monitor none -serial stdio
            -semihosting-config enable=on,target=native -kernel "$<TARGET_FILE:${target}>"
    DEPENDS ${target}
    USES_TERMINAL
    VERBATIM)
endfunction()
