#include <cctype>
#include <string>

#include "meniscus/io.h"

namespace meniscus {

long frameNumberFromName(std::string_view fileName) {
    std::string_view stem = fileName.substr(0, fileName.find('.'));
    std::size_t end = stem.size();
    while (end > 0 && !std::isdigit(static_cast<unsigned char>(stem[end - 1]))) --end;
    std::size_t begin = end;
    while (begin > 0 && std::isdigit(static_cast<unsigned char>(stem[begin - 1]))) --begin;
    if (begin == end || end - begin > 9) return -1;
    return std::stol(std::string(stem.substr(begin, end - begin)));
}

}  // namespace meniscus
