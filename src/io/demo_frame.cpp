// The bundled demo frame, embedded in the library at build time with the
// assembler's .incbin (CMake passes the path), so `meniscus demo` and
// Python's meniscus.demo() need no file next to the binary.
#include "meniscus/io.h"

__asm__(".pushsection .rodata\n"
        ".balign 16\n"
        ".global meniscus_demo_begin\n"
        "meniscus_demo_begin:\n"
        ".incbin \"" MENISCUS_DEMO_FILE "\"\n"
        ".global meniscus_demo_end\n"
        "meniscus_demo_end:\n"
        ".popsection\n");

extern "C" const std::uint8_t meniscus_demo_begin[];
extern "C" const std::uint8_t meniscus_demo_end[];

namespace meniscus {

std::span<const std::uint8_t> demoFrameBytes() {
    return {meniscus_demo_begin, std::size_t(meniscus_demo_end - meniscus_demo_begin)};
}

}  // namespace meniscus
