/* System calls Fortran lacks: mkdir -p, signal flags, isatty, atomic rename.
 * SPDX-License-Identifier: MIT
 * SIGINT/SIGTERM only set a flag; the time loop polls it, finishes the step, writes a
 * checkpoint and stops cleanly (issue 8). */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

static volatile sig_atomic_t received = 0;

static void on_signal(int sig) { received = sig; }

/* Install the handlers for SIGINT and SIGTERM. Returns 0 on success. */
int tubempm_install_signals(void) {
  struct sigaction sa;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  if (sigaction(SIGINT, &sa, NULL) != 0) return -1;
  if (sigaction(SIGTERM, &sa, NULL) != 0) return -1;
  return 0;
}

/* The signal received since start (0 if none). */
int tubempm_signal_received(void) { return (int)received; }

/* 1 when standard output is a terminal. */
int tubempm_stdout_isatty(void) { return isatty(STDOUT_FILENO) ? 1 : 0; }

/* mkdir -p for a NUL-terminated path. Returns 0 or errno; msg gets strerror (len bytes). */
int tubempm_mkdir_p(const char *path, char *msg, int len) {
  char buf[4096];
  size_t n = strlen(path);
  if (n == 0 || n >= sizeof buf) { snprintf(msg, (size_t)len, "path empty or too long"); return EINVAL; }
  memcpy(buf, path, n + 1);
  for (size_t i = 1; i <= n; i++) {
    if (buf[i] == '/' || buf[i] == '\0') {
      char c = buf[i];
      buf[i] = '\0';
      if (mkdir(buf, 0777) != 0 && errno != EEXIST) {
        int e = errno;
        snprintf(msg, (size_t)len, "%s: %s", buf, strerror(e));
        return e;
      }
      buf[i] = c;
    }
  }
  struct stat st;
  if (stat(path, &st) != 0 || !S_ISDIR(st.st_mode)) {
    snprintf(msg, (size_t)len, "%s is not a directory", path);
    return ENOTDIR;
  }
  if (access(path, W_OK) != 0) {
    int e = errno;
    snprintf(msg, (size_t)len, "%s is not writable: %s", path, strerror(e));
    return e;
  }
  msg[0] = '\0';
  return 0;
}

/* Atomic rename (same file system). Returns 0 or errno. */
int tubempm_rename(const char *from, const char *to, char *msg, int len) {
  if (rename(from, to) != 0) {
    int e = errno;
    snprintf(msg, (size_t)len, "rename %s -> %s: %s", from, to, strerror(e));
    return e;
  }
  msg[0] = '\0';
  return 0;
}

/* Exit with `code` and nothing else on the terminal (Fortran's ERROR STOP prints its own line
 * and, in debug builds, a backtrace). The caller has flushed its Fortran units; exit() runs the
 * Fortran runtime's own clean-up, which closes them. */
void tubempm_exit(int code) {
  fflush(NULL);
  exit(code);
}
