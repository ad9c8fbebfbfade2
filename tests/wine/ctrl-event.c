/*
 * TEST-ONLY helper for tests/wine/run.sh, never shipped: runs a command in this process's console, waits,
 * then does to that console what a user does.
 *
 * Usage: ctrl-event.exe ACTION DELAY_MS COMMAND_LINE
 *   ACTION 0: GenerateConsoleCtrlEvent(CTRL_C_EVENT), as for a Ctrl-C typed in the console
 *   ACTION 1: GenerateConsoleCtrlEvent(CTRL_BREAK_EVENT), as for Ctrl-Break
 *   ACTION 2: WM_CLOSE to the console window, as for its close button (Windows then sends CTRL_CLOSE_EVENT)
 * Without a console (no terminal), one is allocated (a window: needs an X display under wine); the command
 * keeps this process's standard handles (redirected files) either way.
 * With CTRL_EVENT_LOG set, the Unix time (s) at which the action was taken is appended to that file.
 * Exit status: the command's; 120 no console; 122 CreateProcess failed; 123 the action failed (the command
 * is then ended).
 */
#include <stdio.h>
#include <stdlib.h>
#include <windows.h>

int main(void)
{
    int argc;
    LPWSTR *argv = CommandLineToArgvW(GetCommandLineW(), &argc);
    if (!argv || argc != 4) {
        fprintf(stderr, "usage: ctrl-event.exe ACTION DELAY_MS COMMAND_LINE\n");
        return 2;
    }
    DWORD action = (DWORD)wcstoul(argv[1], NULL, 10);
    DWORD delay = (DWORD)wcstoul(argv[2], NULL, 10);
    HANDLE in = GetStdHandle(STD_INPUT_HANDLE);
    HANDLE out = GetStdHandle(STD_OUTPUT_HANDLE);
    HANDLE err = GetStdHandle(STD_ERROR_HANDLE);
    /* A process wine starts without a terminal has a console handle that no console answers: replace it. */
    if (!GetConsoleCP() && !(FreeConsole() && AllocConsole())) {
        fprintf(stderr, "ctrl-event: no console and none could be allocated (%lu)\n", GetLastError());
        return 120;
    }
    STARTUPINFOW si;
    ZeroMemory(&si, sizeof(si));
    si.cb = sizeof(si);
    si.dwFlags = STARTF_USESTDHANDLES;
    si.hStdInput = in;
    si.hStdOutput = out;
    si.hStdError = err;
    PROCESS_INFORMATION pi;
    if (!CreateProcessW(NULL, argv[3], NULL, NULL, TRUE, 0, NULL, NULL, &si, &pi)) {
        fprintf(stderr, "ctrl-event: cannot start the command (%lu)\n", GetLastError());
        return 122;
    }
    /* The event goes to every process of the console (group 0), this one too: ignore it here, once the child
     * has started (a child created later would inherit "ignore Ctrl-C"). */
    SetConsoleCtrlHandler(NULL, TRUE);
    if (WaitForSingleObject(pi.hProcess, delay) == WAIT_TIMEOUT) {
        /* FILETIME counts 100 ns from 1601; wine's clock is the host's. Taken before the action. */
        FILETIME now;
        GetSystemTimeAsFileTime(&now);
        ULONGLONG ticks = ((ULONGLONG)now.dwHighDateTime << 32) | now.dwLowDateTime;
        BOOL done;
        if (action == 2) {
            HWND window = GetConsoleWindow();
            done = window && PostMessageW(window, WM_CLOSE, 0, 0);
        } else {
            done = GenerateConsoleCtrlEvent(action, 0);
        }
        DWORD error = GetLastError();
        const char *log = getenv("CTRL_EVENT_LOG");
        FILE *file = log ? fopen(log, "a") : NULL;
        if (file) {
            fprintf(file, "%.6f %lu %d\n", (double)(ticks - 116444736000000000ULL) / 1e7, action, done);
            fclose(file);
        }
        if (!done) {
            fprintf(stderr, "ctrl-event: action %lu failed (%lu)\n", action, error);
            TerminateProcess(pi.hProcess, 123);
            return 123;
        }
    }
    WaitForSingleObject(pi.hProcess, INFINITE);
    DWORD code = 0;
    GetExitCodeProcess(pi.hProcess, &code);
    return (int)code;
}
