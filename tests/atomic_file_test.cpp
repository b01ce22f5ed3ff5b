// Outputs are written to a temporary file and renamed (src/io/atomic_file.cpp);
// a symbolic link as the output is written through, so it stays a link.
#include <gtest/gtest.h>

#include <filesystem>

#include "io/atomic_file.h"
#include "test_util.h"

namespace meniscus {
namespace {

namespace fs = std::filesystem;

Status writeText(const fs::path& path, const std::string& text) {
    return writeAtomically(path, [&](const fs::path& tmp) {
        test::writeText(tmp, text);
        return okStatus();
    });
}

std::string readText(const fs::path& p) {
    const auto b = test::readBytes(p);
    return {b.begin(), b.end()};
}

TEST(AtomicFile, ReplacesAFileAndLeavesNoTemporary) {
    const fs::path dir = test::tempDir() / "atomic_plain";
    fs::remove_all(dir);
    fs::create_directories(dir);
    ASSERT_TRUE(writeText(dir / "out.txt", "one").ok());
    ASSERT_TRUE(writeText(dir / "out.txt", "two").ok());
    EXPECT_EQ(readText(dir / "out.txt"), "two");
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}

// Regression: a symlinked output was replaced by a regular file.
TEST(AtomicFile, WritesThroughASymbolicLink) {
    const fs::path dir = test::tempDir() / "atomic_link";
    fs::remove_all(dir);
    fs::create_directories(dir / "real");
    test::writeText(dir / "real" / "target.txt", "old");
    fs::create_symlink(fs::path("real") / "target.txt", dir / "link.txt");      // relative link
    fs::create_symlink(dir / "link.txt", dir / "link2.txt");                     // a link to the link
    ASSERT_TRUE(writeText(dir / "link2.txt", "new").ok());
    EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir / "link.txt")));
    EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir / "link2.txt")));
    EXPECT_EQ(readText(dir / "real" / "target.txt"), "new");
    EXPECT_EQ(std::distance(fs::directory_iterator(dir / "real"), fs::directory_iterator()), 1);
    // A dangling link: its target is created.
    fs::create_symlink(fs::path("real") / "fresh.txt", dir / "dangling.txt");
    ASSERT_TRUE(writeText(dir / "dangling.txt", "fresh").ok());
    EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir / "dangling.txt")));
    EXPECT_EQ(readText(dir / "real" / "fresh.txt"), "fresh");
}

}  // namespace
}  // namespace meniscus
