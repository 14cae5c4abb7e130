// tools/imageio/os.hpp: the POSIX half, then the Windows half.
#include "imageio/os.hpp"

#include <cerrno>
#include <cstring>
#include <limits>

#if defined(_WIN32)
#include <fcntl.h>
#include <io.h>
#include <sys/stat.h>
#ifndef NOMINMAX
#define NOMINMAX  // windows.h would define min and max as macros
#endif
#include <windows.h>
// After windows.h:
#include <shellapi.h>
#else
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#endif

namespace reproject::io::os {

const char* describe(Kind kind) {
  switch (kind) {
    case Kind::directory: return "a directory";
#if defined(_WIN32)
    case Kind::pipe: return "a pipe";
#else
    case Kind::pipe: return "a FIFO";
#endif
    case Kind::character_device: return "a character device";
    case Kind::block_device: return "a block device";
    case Kind::socket: return "a socket";
    case Kind::missing: return "missing";
    case Kind::regular: return "a regular file";
    case Kind::other: break;
  }
  return "not a regular file";
}

#if !defined(_WIN32)

std::filesystem::path to_path(const std::string& utf8) { return std::filesystem::path(utf8); }
std::string from_path(const std::filesystem::path& path) { return path.string(); }

namespace {

Kind kind_of_mode(mode_t mode) {
  if (S_ISREG(mode)) return Kind::regular;
  if (S_ISDIR(mode)) return Kind::directory;
  if (S_ISFIFO(mode)) return Kind::pipe;
  if (S_ISCHR(mode)) return Kind::character_device;
  if (S_ISBLK(mode)) return Kind::block_device;
  if (S_ISSOCK(mode)) return Kind::socket;
  return Kind::other;
}

}  // namespace

Kind kind_of(const std::string& path) {
  struct stat info = {};
  if (::stat(path.c_str(), &info) != 0) return Kind::missing;
  return kind_of_mode(info.st_mode);
}

long process_id() { return static_cast<long>(::getpid()); }

std::string last_error_text() { return errno != 0 ? std::strerror(errno) : "unknown error"; }

Input open_input(const std::string& path) {
  // A FIFO nobody writes to would block open() itself: opened without blocking, type checked first.
  Input in;
  errno = 0;
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) {
    in.error = last_error_text();
    return in;
  }
  struct stat info = {};
  if (::fstat(fd, &info) != 0) {
    in.error = last_error_text();
    ::close(fd);
    return in;
  }
  in.kind = kind_of_mode(info.st_mode);
  if (in.kind != Kind::regular) {
    ::close(fd);
    return in;
  }
  // A regular file's reads never block; the flag is cleared anyway, so that the FILE reads as usual.
  const int flags = ::fcntl(fd, F_GETFL);
  if (flags != -1) ::fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);
  in.file = ::fdopen(fd, "rb");
  if (in.file == nullptr) {
    in.error = last_error_text();
    in.kind = Kind::missing;
    ::close(fd);
  }
  return in;
}

std::FILE* create_new(const std::string& path, bool* exists, std::string* error) {
  errno = 0;
  std::FILE* file = std::fopen(path.c_str(), "wbx");
  *exists = file == nullptr && errno == EEXIST;
  if (file == nullptr) *error = last_error_text();
  return file;
}

std::FILE* open_file(const std::string& path, const char* mode) { return std::fopen(path.c_str(), mode); }

bool file_status(std::FILE* file, FileStatus* out) {
  struct stat info = {};
  if (::fstat(fileno(file), &info) != 0) return false;
  out->regular = S_ISREG(info.st_mode);
  out->directory = S_ISDIR(info.st_mode);
  out->size = static_cast<std::int64_t>(info.st_size);
  return true;
}

std::int64_t tell(std::FILE* file) { return static_cast<std::int64_t>(::ftello(file)); }

bool seek(std::FILE* file, std::uint64_t position) {
  if (position > static_cast<std::uint64_t>(std::numeric_limits<off_t>::max())) return false;
  return ::fseeko(file, static_cast<off_t>(position), SEEK_SET) == 0;
}

bool replace_file(const std::string& from, const std::string& to, std::string* error) {
  errno = 0;
  if (::rename(from.c_str(), to.c_str()) == 0) return true;
  *error = last_error_text();
  return false;
}

bool hard_link(const std::string& existing, const std::string& link) {
  return ::link(existing.c_str(), link.c_str()) == 0;
}

void copy_permissions(const std::string& from, const std::string& to) {
  struct stat info = {};
  if (::stat(from.c_str(), &info) == 0) ::chmod(to.c_str(), info.st_mode & 07777);
}

bool same_file(const std::string& a, const std::string& b) {
  struct stat sa = {}, sb = {};
  return ::stat(a.c_str(), &sa) == 0 && ::stat(b.c_str(), &sb) == 0 && sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

std::vector<std::string> arguments(int argc, char** argv) { return std::vector<std::string>(argv, argv + argc); }

bool remove_file(const char* path) noexcept { return ::unlink(path) == 0; }
bool remove_directory(const char* path) noexcept { return ::rmdir(path) == 0; }

#else  // Windows

namespace {

std::wstring wide(const std::string& utf8) {
  if (utf8.empty()) return {};
  const int n = MultiByteToWideChar(CP_UTF8, 0, utf8.data(), static_cast<int>(utf8.size()), nullptr, 0);
  std::wstring out(static_cast<std::size_t>(n > 0 ? n : 0), L'\0');
  if (n > 0) MultiByteToWideChar(CP_UTF8, 0, utf8.data(), static_cast<int>(utf8.size()), out.data(), n);
  return out;
}

std::string narrow(const std::wstring& utf16) {
  if (utf16.empty()) return {};
  const int n = WideCharToMultiByte(CP_UTF8, 0, utf16.data(), static_cast<int>(utf16.size()), nullptr, 0, nullptr, nullptr);
  std::string out(static_cast<std::size_t>(n > 0 ? n : 0), '\0');
  if (n > 0) WideCharToMultiByte(CP_UTF8, 0, utf16.data(), static_cast<int>(utf16.size()), out.data(), n, nullptr, nullptr);
  return out;
}

std::string error_text(DWORD code) {
  char* text = nullptr;
  const DWORD n = FormatMessageA(FORMAT_MESSAGE_ALLOCATE_BUFFER | FORMAT_MESSAGE_FROM_SYSTEM | FORMAT_MESSAGE_IGNORE_INSERTS,
                                 nullptr, code, MAKELANGID(LANG_ENGLISH, SUBLANG_DEFAULT), reinterpret_cast<char*>(&text), 0,
                                 nullptr);
  std::string out = n > 0 && text != nullptr ? std::string(text, n) : "error " + std::to_string(code);
  if (text != nullptr) LocalFree(text);
  while (!out.empty() && (out.back() == '\n' || out.back() == '\r' || out.back() == ' ' || out.back() == '.')) out.pop_back();
  return out;
}

// A C stream over a handle (the CRT takes ownership of it).
std::FILE* stream_of(HANDLE handle, int flags, const char* mode) {
  const int fd = _open_osfhandle(reinterpret_cast<intptr_t>(handle), flags | _O_BINARY);
  if (fd < 0) {
    CloseHandle(handle);
    return nullptr;
  }
  std::FILE* file = _fdopen(fd, mode);
  if (file == nullptr) _close(fd);
  return file;
}

Kind kind_of_handle(HANDLE handle) {
  switch (GetFileType(handle)) {
    case FILE_TYPE_PIPE: return Kind::pipe;
    case FILE_TYPE_CHAR: return Kind::character_device;
    case FILE_TYPE_DISK: break;
    default: return Kind::other;
  }
  BY_HANDLE_FILE_INFORMATION info;
  if (!GetFileInformationByHandle(handle, &info)) return Kind::other;
  return (info.dwFileAttributes & FILE_ATTRIBUTE_DIRECTORY) != 0 ? Kind::directory : Kind::regular;
}

// Opens for reading attributes only (a directory too); INVALID_HANDLE_VALUE if it cannot.
HANDLE open_to_inspect(const std::string& path) {
  return CreateFileW(wide(path).c_str(), FILE_READ_ATTRIBUTES, FILE_SHARE_READ | FILE_SHARE_WRITE | FILE_SHARE_DELETE,
                     nullptr, OPEN_EXISTING, FILE_FLAG_BACKUP_SEMANTICS, nullptr);
}

}  // namespace

std::filesystem::path to_path(const std::string& utf8) { return std::filesystem::path(wide(utf8)); }
std::string from_path(const std::filesystem::path& path) { return narrow(path.wstring()); }

Kind kind_of(const std::string& path) {
  // Through a handle, so that devices (NUL, CON) and pipes are seen as such.
  const HANDLE handle = open_to_inspect(path);
  if (handle == INVALID_HANDLE_VALUE) return Kind::missing;
  const Kind kind = kind_of_handle(handle);
  CloseHandle(handle);
  return kind;
}

long process_id() { return static_cast<long>(GetCurrentProcessId()); }

std::string last_error_text() { return error_text(GetLastError()); }

Input open_input(const std::string& path) {
  // GetFileType before any read: a pipe, a console or a device such as NUL is refused at once. A
  // named pipe's client end connects, or fails as busy, without waiting. A directory opens only
  // with FILE_FLAG_BACKUP_SEMANTICS: asked for, so that it is named as such.
  Input in;
  const HANDLE handle = CreateFileW(wide(path).c_str(), GENERIC_READ, FILE_SHARE_READ | FILE_SHARE_WRITE | FILE_SHARE_DELETE,
                                    nullptr, OPEN_EXISTING, FILE_FLAG_BACKUP_SEMANTICS, nullptr);
  if (handle == INVALID_HANDLE_VALUE) {
    in.error = last_error_text();
    return in;
  }
  in.kind = kind_of_handle(handle);
  if (in.kind != Kind::regular) {
    CloseHandle(handle);
    return in;
  }
  in.file = stream_of(handle, _O_RDONLY, "rb");
  if (in.file == nullptr) {
    in.error = std::strerror(errno);
    in.kind = Kind::missing;
  }
  return in;
}

std::FILE* create_new(const std::string& path, bool* exists, std::string* error) {
  const HANDLE handle = CreateFileW(wide(path).c_str(), GENERIC_WRITE, FILE_SHARE_READ | FILE_SHARE_DELETE, nullptr,
                                    CREATE_NEW, FILE_ATTRIBUTE_NORMAL, nullptr);
  if (handle == INVALID_HANDLE_VALUE) {
    const DWORD code = GetLastError();
    *exists = code == ERROR_FILE_EXISTS || code == ERROR_ALREADY_EXISTS;
    *error = error_text(code);
    return nullptr;
  }
  *exists = false;
  std::FILE* file = stream_of(handle, _O_WRONLY, "wb");
  if (file == nullptr) *error = std::strerror(errno);
  return file;
}

std::FILE* open_file(const std::string& path, const char* mode) { return _wfopen(wide(path).c_str(), wide(mode).c_str()); }

bool file_status(std::FILE* file, FileStatus* out) {
  struct _stat64 info = {};
  if (_fstat64(_fileno(file), &info) != 0) return false;
  out->regular = (info.st_mode & _S_IFMT) == _S_IFREG;
  out->directory = (info.st_mode & _S_IFMT) == _S_IFDIR;
  out->size = static_cast<std::int64_t>(info.st_size);
  return true;
}

std::int64_t tell(std::FILE* file) { return static_cast<std::int64_t>(_ftelli64(file)); }

bool seek(std::FILE* file, std::uint64_t position) {
  if (position > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) return false;
  return _fseeki64(file, static_cast<__int64>(position), SEEK_SET) == 0;
}

bool replace_file(const std::string& from, const std::string& to, std::string* error) {
  if (MoveFileExW(wide(from).c_str(), wide(to).c_str(), MOVEFILE_REPLACE_EXISTING | MOVEFILE_WRITE_THROUGH)) return true;
  *error = last_error_text();
  return false;
}

bool hard_link(const std::string& existing, const std::string& link) {
  return CreateHardLinkW(wide(link).c_str(), wide(existing).c_str(), nullptr) != 0;
}

void copy_permissions(const std::string&, const std::string&) {}

std::vector<std::string> arguments(int argc, char** argv) {
  SetConsoleOutputCP(CP_UTF8);
  int count = 0;
  wchar_t** wide_argv = CommandLineToArgvW(GetCommandLineW(), &count);
  if (wide_argv == nullptr) return std::vector<std::string>(argv, argv + argc);
  std::vector<std::string> out;
  for (int i = 0; i < count; ++i) out.push_back(narrow(wide_argv[i]));
  LocalFree(wide_argv);
  return out;
}

bool same_file(const std::string& a, const std::string& b) {
  const HANDLE ha = open_to_inspect(a);
  if (ha == INVALID_HANDLE_VALUE) return false;
  const HANDLE hb = open_to_inspect(b);
  bool same = false;
  BY_HANDLE_FILE_INFORMATION ia, ib;
  if (hb != INVALID_HANDLE_VALUE && GetFileInformationByHandle(ha, &ia) && GetFileInformationByHandle(hb, &ib)) {
    same = ia.dwVolumeSerialNumber == ib.dwVolumeSerialNumber && ia.nFileIndexHigh == ib.nFileIndexHigh &&
           ia.nFileIndexLow == ib.nFileIndexLow;
  }
  CloseHandle(ha);
  if (hb != INVALID_HANDLE_VALUE) CloseHandle(hb);
  return same;
}

// Called from the console control handler's thread, where allocating is allowed.
bool remove_file(const char* path) noexcept {
  try {
    return DeleteFileW(wide(path).c_str()) != 0;
  } catch (...) {
    return false;
  }
}
bool remove_directory(const char* path) noexcept {
  try {
    return RemoveDirectoryW(wide(path).c_str()) != 0;
  } catch (...) {
    return false;
  }
}

#endif

}  // namespace reproject::io::os
