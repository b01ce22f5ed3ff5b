// Small helpers shared by the tests: data paths, temp dirs, file bytes, gzip.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace meniscus::test {

std::filesystem::path testData(const std::string& rel);  // tests/data/REL
std::filesystem::path repoData(const std::string& rel);  // data/REL

// A fresh, empty directory unique to the calling test; removed by the next run.
std::filesystem::path tempDir();

std::vector<std::uint8_t> readBytes(const std::filesystem::path& p);
void writeBytes(const std::filesystem::path& p, const std::vector<std::uint8_t>& bytes);
void writeText(const std::filesystem::path& p, const std::string& text);
std::vector<std::uint8_t> toBytes(const std::string& s);

// gzip-compress (for making .bgeo.gz-like test inputs).
std::vector<std::uint8_t> gzipBytes(const std::vector<std::uint8_t>& raw);

// Runs a shell command; returns its exit status, captures stdout+stderr.
int runCommand(const std::string& cmd, std::string* output = nullptr);

// Path of the built CLI.
std::string cliPath();

}  // namespace meniscus::test
