# CMake toolchain file: bare-metal Cortex-M4 with Debian's arm-none-eabi GCC.
#
#   cmake -S . -B build-mcu -DCMAKE_TOOLCHAIN_FILE=<btgen>/cmake/toolchain/arm-none-eabi-cortex-m4.cmake
#
# Packages: gcc-arm-none-eabi, libstdc++-arm-none-eabi-newlib (and
# qemu-system-arm to run the images: see mcu/README.md).
#
# What it sets, for every target of the build:
#   -mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16
#       the Cortex-M4F (single-precision FPU; doubles are in software)
#   -fno-exceptions -fno-rtti -fno-threadsafe-statics -fno-use-cxa-atexit
#       no unwinding tables, no type info, no guard locks, no exit-time
#       destructor registry: a generated mission needs none of them
#   -ffunction-sections -fdata-sections, and --gc-sections at the link
#   -DBTGEN_BARE_METAL=1
#       the runtime's bare-metal build: number <-> text conversions that do
#       not allocate (newlib's strtod and printf("%f") do), and the headers
#       that need an operating system (Groot2, .btlog, AsyncCall) refuse to
#       compile
#   newlib-nano (--specs=nano.specs), no start files: the board support
#       (mcu/bsp/, cmake/btgen_mcu.cmake) brings the vector table, the reset
#       handler, the linker script and an _sbrk that stops any allocation.
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR arm)

set(BTGEN_MCU_TRIPLE arm-none-eabi CACHE STRING "prefix of the bare-metal GCC tools")
set(CMAKE_C_COMPILER ${BTGEN_MCU_TRIPLE}-gcc)
set(CMAKE_CXX_COMPILER ${BTGEN_MCU_TRIPLE}-g++)
set(CMAKE_ASM_COMPILER ${BTGEN_MCU_TRIPLE}-gcc)
set(CMAKE_OBJCOPY ${BTGEN_MCU_TRIPLE}-objcopy CACHE FILEPATH "objcopy of the bare-metal tools")
set(CMAKE_SIZE ${BTGEN_MCU_TRIPLE}-size CACHE FILEPATH "size of the bare-metal tools")

# The compiler cannot link a program before the board support exists: test it as a library.
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)

set(BTGEN_MCU_CPU_FLAGS "-mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16")
set(CMAKE_C_FLAGS_INIT "${BTGEN_MCU_CPU_FLAGS} -ffunction-sections -fdata-sections")
set(CMAKE_CXX_FLAGS_INIT
    "${BTGEN_MCU_CPU_FLAGS} -ffunction-sections -fdata-sections -fno-exceptions -fno-rtti -fno-threadsafe-statics -fno-use-cxa-atexit -DBTGEN_BARE_METAL=1")
set(CMAKE_ASM_FLAGS_INIT "${BTGEN_MCU_CPU_FLAGS}")
set(CMAKE_EXE_LINKER_FLAGS_INIT "${BTGEN_MCU_CPU_FLAGS} --specs=nano.specs -nostartfiles -Wl,--gc-sections")
set(CMAKE_EXECUTABLE_SUFFIX_C .elf)
set(CMAKE_EXECUTABLE_SUFFIX_CXX .elf)

# No sysroot: Python (for btgen) and the host tools are found on the host as usual.
