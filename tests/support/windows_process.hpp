// Windows only: starting a program and sending it Ctrl-C, for the tests that interrupt the tool
// or a writer (the POSIX tests fork and kill). Header-only; included under _WIN32.
#pragma once

#ifndef NOMINMAX
#define NOMINMAX  // windows.h would define min and max as macros
#endif
#include <windows.h>
// windows.h defines near and far as empty macros (16-bit pointers): names of ours.
#undef near
#undef far

#include <string>

namespace rptest {

// UTF-8 to UTF-16.
inline std::wstring wide(const std::string& utf8) {
  if (utf8.empty()) return {};
  const int n = MultiByteToWideChar(CP_UTF8, 0, utf8.data(), static_cast<int>(utf8.size()), nullptr, 0);
  std::wstring out(static_cast<std::size_t>(n), L'\0');
  MultiByteToWideChar(CP_UTF8, 0, utf8.data(), static_cast<int>(utf8.size()), out.data(), n);
  return out;
}

// One argument quoted for CommandLineToArgvW (the rules every MinGW and MSVC program parses by).
inline std::wstring quote_argument(const std::wstring& argument) {
  if (!argument.empty() && argument.find_first_of(L" \t\"") == std::wstring::npos) return argument;
  std::wstring out = L"\"";
  std::size_t backslashes = 0;
  for (wchar_t c : argument) {
    if (c == L'\\') {
      ++backslashes;
      continue;
    }
    out.append(c == L'"' ? 2 * backslashes + 1 : backslashes, L'\\');
    backslashes = 0;
    out.push_back(c);
  }
  out.append(2 * backslashes, L'\\');
  out.push_back(L'"');
  return out;
}

// Starts `command_line` in `directory` (empty: ours), its standard input NUL and its output and
// errors into the given handles (inheritable; NULL: NUL too). With `own_console`, in a console of
// its own (hidden), so that it can be sent Ctrl-C without reaching this process's group.
inline bool start_process(std::wstring command_line, const std::wstring& directory, HANDLE out, HANDLE err,
                          bool own_console, PROCESS_INFORMATION* process, HANDLE job = nullptr) {
  SECURITY_ATTRIBUTES inherit = {sizeof inherit, nullptr, TRUE};
  const HANDLE nul = CreateFileW(L"NUL", GENERIC_READ | GENERIC_WRITE, FILE_SHARE_READ | FILE_SHARE_WRITE, &inherit,
                                 OPEN_EXISTING, 0, nullptr);
  STARTUPINFOW startup = {};
  startup.cb = sizeof startup;
  startup.dwFlags = STARTF_USESTDHANDLES | STARTF_USESHOWWINDOW;
  startup.wShowWindow = SW_HIDE;
  startup.hStdInput = nul;
  startup.hStdOutput = out != nullptr ? out : nul;
  startup.hStdError = err != nullptr ? err : nul;
  const DWORD flags = (own_console ? CREATE_NEW_CONSOLE : 0) | (job != nullptr ? CREATE_SUSPENDED : 0);
  const BOOL ok = CreateProcessW(nullptr, command_line.data(), nullptr, nullptr, TRUE, flags, nullptr,
                                 directory.empty() ? nullptr : directory.c_str(), &startup, process);
  CloseHandle(nul);
  if (ok && job != nullptr) {
    AssignProcessToJobObject(job, process->hProcess);
    ResumeThread(process->hThread);
  }
  return ok != 0;
}

// Ctrl-C to the process group of the console `process` runs in (started with own_console): this
// process attaches to that console for the moment, ignoring the event itself. (Wine delivers
// CTRL_C_EVENT to a console's group 0 but not CTRL_BREAK_EVENT to a process group; Windows does
// both: the tool's handler treats every event alike.)
inline bool send_ctrl_c(DWORD process_id) {
  FreeConsole();
  if (!AttachConsole(process_id)) return false;
  SetConsoleCtrlHandler(nullptr, TRUE);
  const bool sent = GenerateConsoleCtrlEvent(CTRL_C_EVENT, 0) != 0;
  FreeConsole();
  SetConsoleCtrlHandler(nullptr, FALSE);
  return sent;
}

}  // namespace rptest
