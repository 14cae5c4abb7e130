// The operating system's side of file handling, for imageio and the tool (tools/cli): POSIX and
// Windows behind one set of functions. Paths are UTF-8 std::strings everywhere; on Windows they
// reach the system through its wide (UTF-16) API, so that any name works whatever the process's
// code page is.
#pragma once

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace reproject::io::os {

// A UTF-8 path as a std::filesystem::path, and back (on POSIX both are the bytes unchanged).
std::filesystem::path to_path(const std::string& utf8);
std::string from_path(const std::filesystem::path& path);

// What a path names (following links).
enum class Kind { missing, regular, directory, pipe, character_device, block_device, socket, other };
Kind kind_of(const std::string& path);
// "a directory", "a FIFO" / "a pipe", "a character device", ...
const char* describe(Kind kind);

// The calling process's id (names of temporary files).
long process_id();

// An open input: a regular file's stream, or why not. Opening never blocks (POSIX: O_NONBLOCK, so
// a FIFO nobody writes to is seen as one; Windows: a named pipe connects or fails at once), and
// the kind is known before a byte is read.
struct Input {
  std::FILE* file = nullptr;  // regular files only
  Kind kind = Kind::missing;
  std::string error;          // why it could not be opened, when kind is missing
};
Input open_input(const std::string& path);

// Creates `path` for writing, failing if it exists (`*exists` then set). On Windows the file may be
// deleted while open (by the clean-up of remove_temporary_files, which may run on another thread:
// the console's control handler). `*error` says why on failure.
std::FILE* create_new(const std::string& path, bool* exists, std::string* error);
// fopen with a UTF-8 path.
std::FILE* open_file(const std::string& path, const char* mode);

// What fstat says of an open file, with a 64-bit size on every system (Windows' `long`, and the
// size in MinGW's and MSVC's default `struct stat`, are 32-bit: files of 2 GB and more).
struct FileStatus {
  bool regular = false;
  bool directory = false;
  std::int64_t size = 0;
};
// False if the system cannot say (errno says why).
bool file_status(std::FILE* file, FileStatus* out);
// The stream's position (-1 on failure, errno set) and a seek to `position` from its start
// (false on failure), 64-bit likewise.
std::int64_t tell(std::FILE* file);
bool seek(std::FILE* file, std::uint64_t position);

// Renames `from` onto `to`, replacing it atomically if it exists (POSIX rename(2); Windows
// MoveFileExW with MOVEFILE_REPLACE_EXISTING | MOVEFILE_WRITE_THROUGH).
bool replace_file(const std::string& from, const std::string& to, std::string* error);
// A second name for an existing file (POSIX link(2), Windows CreateHardLinkW).
bool hard_link(const std::string& existing, const std::string& link);
// The POSIX permission bits of `from` given to `to` (Windows: nothing; the new file has the
// folder's inherited access rights, as the old one had).
void copy_permissions(const std::string& from, const std::string& to);
// Whether both paths name the same existing file.
bool same_file(const std::string& a, const std::string& b);
// Removes a file / an empty directory; false if it could not. POSIX: async-signal-safe.
bool remove_file(const char* path) noexcept;
bool remove_directory(const char* path) noexcept;

// The command's arguments as UTF-8 (POSIX: argv as it is; Windows: the wide command line, since
// main's argv holds the ANSI code page's bytes, where most non-ASCII names cannot be spelled). On
// Windows, console output is switched to UTF-8 too.
std::vector<std::string> arguments(int argc, char** argv);

// The text of the last system error (errno on POSIX, GetLastError on Windows).
std::string last_error_text();

}  // namespace reproject::io::os
