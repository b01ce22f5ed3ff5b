// Outputs are written to a temporary file and renamed (src/io/atomic_file.cpp);
// a symbolic link as the output is written through, so it stays a link; an
// output that is not a regular file (a device, a FIFO, a folder), named or
// linked to, is refused before anything is written.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>

#include <unistd.h>

#include <sys/stat.h>
#include <sys/sysmacros.h>

#include "io/atomic_file.h"
#include "meniscus/io.h"
#include "meniscus/temporaries.h"
#include "test_util.h"

namespace meniscus::atomic_file_test_local {
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

// Regression: an output that was a link to a FIFO or a device was replaced by
// a regular file (the rename went over the FIFO or the device node). Refused
// now, as the command line's mistake, before the write and any rename.
TEST(AtomicFile, RefusesToReplaceWhatIsNotARegularFile) {
    const fs::path dir = test::tempDir() / "atomic_not_a_file";
    fs::remove_all(dir);
    fs::create_directories(dir / "folder");
    ASSERT_EQ(::mkfifo((dir / "fifo").c_str(), 0600), 0);
    fs::create_symlink(dir / "fifo", dir / "to_fifo.png");
    bool wrote = false;
    const auto write = [&](const fs::path& path) {
        return writeAtomically(path, [&](const fs::path& tmp) {
            wrote = true;
            test::writeText(tmp, "x");
            return okStatus();
        });
    };
    auto st = write(dir / "to_fifo.png");
    ASSERT_FALSE(st.ok());
    EXPECT_TRUE(st.error().usage);
    EXPECT_NE(st.error().describe().find("to_fifo.png: is a link to a named pipe (FIFO), not a file; choose "
                                         "another output"),
              std::string::npos)
        << st.error().describe();
    EXPECT_FALSE(wrote);
    EXPECT_TRUE(fs::is_fifo(dir / "fifo"));
    st = write(dir / "fifo");  // named itself
    ASSERT_FALSE(st.ok());
    EXPECT_NE(st.error().describe().find("is a named pipe (FIFO), not a file"), std::string::npos);
    EXPECT_TRUE(fs::is_fifo(dir / "fifo"));
    st = write(dir / "folder");
    ASSERT_FALSE(st.ok());
    EXPECT_NE(st.error().describe().find("is a directory, not a file"), std::string::npos);
    EXPECT_TRUE(fs::is_directory(dir / "folder"));
    // A device node of its own, a copy of /dev/null (root can make one).
    if (::mknod((dir / "null").c_str(), S_IFCHR | 0666, makedev(1, 3)) == 0) {
        fs::create_symlink(dir / "null", dir / "to_null.png");
        st = write(dir / "to_null.png");
        ASSERT_FALSE(st.ok());
        EXPECT_NE(st.error().describe().find("is a link to a device, not a file"), std::string::npos);
        EXPECT_TRUE(fs::is_character_file(fs::symlink_status(dir / "null")));
    }
    EXPECT_FALSE(wrote);
    // Nothing left behind: no temporary beside any of them.
    for (const auto& e : fs::directory_iterator(dir))
        EXPECT_NE(e.path().filename().string().rfind(".", 0), 0u) << e.path();
}

// A killed run's temporary (PendingFile's name with a PID no process has) is
// removed; a live process's, a name off the pattern, a folder or a link of
// that name, and a temporary newer than `olderThan` stay.
TEST(AtomicFile, RemovesOnlyTheTemporariesOfDeadProcesses) {
    const fs::path dir = test::tempDir();
    // The name begin() gives, from this (live) process.
    auto pending = PendingFile::begin(dir / "f.png");
    ASSERT_TRUE(pending.ok());
    test::writeText(pending->tmp(), "in progress");
    const std::string pid = std::to_string(::getpid());
    for (const char* name : {".f_0035.png.tmp999999_0", ".out.mp4.tmp999998_12", ".x.tmp999999_0", "x.png.tmp999999_0",
                             ".x.png.tmp999999_", ".x.png.tmp999999_0.bak", ".x.png.tmp_0", ".tmp999999_0",
                             ".x.png.tmp99999999999_0"})
        test::writeText(dir / name, "partial");
    fs::create_directories(dir / ".d.png.tmp999999_0");
    fs::create_symlink(dir / "x.png.tmp999999_0", dir / ".l.png.tmp999999_0");
    const auto removed = removeStaleTemporaries(dir);
    std::set<std::string> names;
    for (const fs::path& p : removed) names.insert(p.filename().string());
    EXPECT_EQ(names, (std::set<std::string>{".f_0035.png.tmp999999_0", ".out.mp4.tmp999998_12", ".x.tmp999999_0"}));
    for (const std::string& name : names) EXPECT_FALSE(fs::exists(dir / name)) << name;
    EXPECT_TRUE(fs::exists(pending->tmp())) << "this process's temporary stays";
    for (const char* name : {"x.png.tmp999999_0", ".x.png.tmp999999_", ".x.png.tmp999999_0.bak", ".x.png.tmp_0",
                             ".tmp999999_0", ".x.png.tmp99999999999_0", ".d.png.tmp999999_0"})
        EXPECT_TRUE(fs::exists(dir / name)) << name;
    EXPECT_TRUE(fs::is_symlink(dir / ".l.png.tmp999999_0"));
    // For a folder shared with other machines: only one unchanged for the age given.
    test::writeText(dir / ".g.png.tmp999999_0", "partial");
    EXPECT_TRUE(removeStaleTemporaries(dir, std::chrono::hours(1)).empty());
    fs::last_write_time(dir / ".g.png.tmp999999_0", fs::file_time_type::clock::now() - std::chrono::hours(2));
    EXPECT_EQ(removeStaleTemporaries(dir, std::chrono::hours(1)).size(), 1u);
    EXPECT_TRUE(removeStaleTemporaries(dir / "missing").empty());
}

}  // namespace
}  // namespace meniscus::atomic_file_test_local
