// Include resolution for the embedded shaders (see shaders.h).
#include "gl/shaders.h"

#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>

#include "shared/text_lines.h"

namespace meniscus::gl {

namespace {

// Shader development: with MENISCUS_SHADER_DIR set, a file of that name in the
// directory replaces the embedded one (edit and re-run without rebuilding;
// A/B timing of variants in one session). Unset: the embedded files only.
std::string overrideSource(std::string_view fileName) {
    const char* dir = std::getenv("MENISCUS_SHADER_DIR");
    if (!dir || !*dir) return {};
    std::ifstream in(std::string(dir) + "/" + std::string(fileName), std::ios::binary);
    if (!in) return {};
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

Status appendResolved(std::string_view fileName, std::set<std::string>& seen, std::string& out) {
    const std::string overridden = overrideSource(fileName);
    const std::string_view text = overridden.empty() ? shaderSource(fileName) : std::string_view(overridden);
    if (text.empty()) return makeError(std::string(fileName), "shader file not embedded in the build");
    seen.insert(std::string(fileName));
    shared::TextLines lines(text);
    for (std::string_view line; lines.next(line);) {
        const std::size_t first = line.find_first_not_of(" \t");
        const std::string_view trimmed = first == std::string_view::npos ? std::string_view{} : line.substr(first);
        if (trimmed.starts_with("#extension GL_GOOGLE_include_directive")) {
            out += '\n';  // keep line numbers of the rest roughly meaningful
            continue;
        }
        if (trimmed.starts_with("#include <")) {
            out += '\n';  // a system header of the C++ side of a src/shared file (inside #ifdef __cplusplus)
            continue;
        }
        if (trimmed.starts_with("#include")) {
            const std::size_t a = trimmed.find('"'), b = trimmed.rfind('"');
            if (a == std::string_view::npos || b <= a)
                return makeError(std::string(fileName), "malformed #include line: " + std::string(line));
            const std::string name(trimmed.substr(a + 1, b - a - 1));
            if (!seen.count(name))
                if (auto st = appendResolved(name, seen, out); !st) return st;
            out += '\n';
            continue;
        }
        out.append(line);
        out += '\n';
    }
    return okStatus();
}

}  // namespace

Result<std::string> resolveIncludes(std::string_view fileName) {
    std::set<std::string> seen;
    std::string out;
    if (auto st = appendResolved(fileName, seen, out); !st) return st.error();
    return out;
}

Result<Program> loadComputeProgram(std::string_view fileName) {
    auto src = resolveIncludes(fileName);
    if (!src) return src.error();
    return computeProgram(*src, std::string(fileName));
}

Result<Program> loadRenderProgram(std::string_view vertexFile, std::string_view fragmentFile) {
    auto vsrc = resolveIncludes(vertexFile);
    if (!vsrc) return vsrc.error();
    auto fsrc = resolveIncludes(fragmentFile);
    if (!fsrc) return fsrc.error();
    auto vs = compileShader(GL_VERTEX_SHADER, *vsrc, std::string(vertexFile));
    if (!vs) return vs.error();
    auto fs = compileShader(GL_FRAGMENT_SHADER, *fsrc, std::string(fragmentFile));
    if (!fs) return fs.error();
    return linkProgram(std::string(vertexFile) + " + " + std::string(fragmentFile), *vs, *fs);
}

}  // namespace meniscus::gl
