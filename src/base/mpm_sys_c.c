/* System calls Fortran lacks: mkdir -p (and whether it could), signal flags, isatty, atomic
 * rename, busy cores, the lock of an output folder.
 * SPDX-License-Identifier: MIT
 * SIGINT/SIGTERM only set a flag (the first one: another, a second or more later, kills at
 * once); the driver polls it before the outputs open (it stops with nothing written) and in
 * the time loop (it finishes the step, writes a checkpoint and stops cleanly; issue 8). */
#define _GNU_SOURCE
#include <errno.h>
#ifdef __linux__
#include <sched.h>
#endif
#include <time.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

/* The first signal and its time (CLOCK_MONOTONIC, ns), read and written only through the
 * __atomic builtins (lock-free, so async-signal-safe): the handler may run on two OpenMP
 * threads at once, and a thread that sees `received` set must see `first_ns` too. */
static int received = 0;
static long long first_ns = 0;

/* Another SIGINT or SIGTERM kills at once (a second Ctrl-C during a long set-up or a slow
 * save), unless it comes within `echo_ns` of the first: one interrupt often arrives twice, as
 * coreutils `timeout` signals the child and then its process group, and a shell's Ctrl-C or
 * Slurm's scancel reach every process of the group. Such an echo is ignored; SA_RESETHAND,
 * used before, let it kill the run with no checkpoint. Only async-signal-safe calls here. */
static const long long echo_ns = 1000000000LL;

static void on_signal(int sig) {
  struct timespec ts;
  long long now, none = 0;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  now = (long long)ts.tv_sec * 1000000000LL + (long long)ts.tv_nsec;
  /* the first arrival stamps the time before `received` is set (release), so that any
   * thread that reads `received` set (acquire) reads the stamp */
  __atomic_compare_exchange_n(&first_ns, &none, now, 0, __ATOMIC_ACQ_REL, __ATOMIC_ACQUIRE);
  if (__atomic_load_n(&received, __ATOMIC_ACQUIRE) == 0) {
    __atomic_store_n(&received, sig, __ATOMIC_RELEASE);
    return;
  }
  if (now - __atomic_load_n(&first_ns, __ATOMIC_ACQUIRE) < echo_ns) return;
  struct sigaction dfl;
  memset(&dfl, 0, sizeof dfl);
  dfl.sa_handler = SIG_DFL;
  sigemptyset(&dfl.sa_mask);
  sigaction(sig, &dfl, NULL);
  raise(sig);
}

/* Install the handlers for SIGINT and SIGTERM. Returns 0 on success. */
int tubempm_install_signals(void) {
  struct sigaction sa;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_signal;
  sa.sa_flags = 0;
  sigemptyset(&sa.sa_mask);
  sigaddset(&sa.sa_mask, SIGINT);        /* one handler at a time */
  sigaddset(&sa.sa_mask, SIGTERM);
  if (sigaction(SIGINT, &sa, NULL) != 0) return -1;
  if (sigaction(SIGTERM, &sa, NULL) != 0) return -1;
  return 0;
}

/* The signal received since start (0 if none). */
int tubempm_signal_received(void) { return __atomic_load_n(&received, __ATOMIC_ACQUIRE); }

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

/* Whether mkdir -p `path` could make it, without making anything: the path, or its nearest
 * existing ancestor, must be a folder this process can write into. Returns 0 or errno; msg
 * gets the reason (len bytes). For `--check`, which writes nothing. */
int tubempm_dir_creatable(const char *path, char *msg, int len) {
  char buf[4096];
  size_t n = strlen(path);
  if (n == 0 || n >= sizeof buf) { snprintf(msg, (size_t)len, "path empty or too long"); return EINVAL; }
  memcpy(buf, path, n + 1);
  for (;;) {
    struct stat st;
    if (stat(buf, &st) == 0) {
      if (!S_ISDIR(st.st_mode)) {
        snprintf(msg, (size_t)len, "%s is not a directory", buf);
        return ENOTDIR;
      }
      if (access(buf, W_OK | X_OK) != 0) {
        int e = errno;
        snprintf(msg, (size_t)len, "%s is not writable: %s", buf, strerror(e));
        return e;
      }
      msg[0] = '\0';
      return 0;
    }
    if (errno != ENOENT) {
      int e = errno;
      snprintf(msg, (size_t)len, "%s: %s", buf, strerror(e));
      return e;
    }
    /* up one level: strip trailing slashes, then the last component */
    size_t k = strlen(buf);
    while (k > 1 && buf[k - 1] == '/') buf[--k] = '\0';
    while (k > 0 && buf[k - 1] != '/') buf[--k] = '\0';
    while (k > 1 && buf[k - 1] == '/') buf[--k] = '\0';
    if (k == 0) { buf[0] = '.'; buf[1] = '\0'; }
  }
}

/* Lock the folder `path` for this process (an exclusive flock on the folder itself, held
 * until the process ends: no file is added, and a killed run leaves no stale lock). Returns 0,
 * -2 when another process holds it, -3 when the file system has no such locks (NFS emulates
 * flock with byte-range locks that a directory cannot take, Lustre without its flock option
 * refuses it), or errno; msg gets the reason. */
int tubempm_lock_dir(const char *path, char *msg, int len) {
  int fd = open(path, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) {
    int e = errno;
    snprintf(msg, (size_t)len, "%s: %s", path, strerror(e));
    return e;
  }
  if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
    int e = errno;
    close(fd);
    snprintf(msg, (size_t)len, "%s: %s", path, strerror(e));
    if (e == EWOULDBLOCK) return -2;
    if (e == ENOLCK || e == ENOSYS || e == EOPNOTSUPP || e == EBADF || e == EINVAL) return -3;
    return e;
  }
  msg[0] = '\0';
  return 0;                                   /* fd stays open: the lock lasts the process */
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

#ifdef __linux__
/* Jiffies of every CPU of the set: busy (all but idle and iowait) and total, from /proc/stat.
 * Returns the number of CPUs read, or -1. */
static int cpu_times(const cpu_set_t *set, unsigned long long *busy, unsigned long long *total) {
  FILE *f = fopen("/proc/stat", "r");
  char line[512];
  int n = 0;
  if (f == NULL) return -1;
  *busy = 0;
  *total = 0;
  while (fgets(line, sizeof line, f) != NULL) {
    int cpu;
    unsigned long long v[8] = {0};
    if (strncmp(line, "cpu", 3) != 0 || line[3] < '0' || line[3] > '9') continue;
    if (sscanf(line + 3, "%d %llu %llu %llu %llu %llu %llu %llu %llu", &cpu, &v[0], &v[1], &v[2],
               &v[3], &v[4], &v[5], &v[6], &v[7]) < 5) continue;
    if (cpu < 0 || cpu >= CPU_SETSIZE || !CPU_ISSET(cpu, set)) continue;
    unsigned long long all = v[0] + v[1] + v[2] + v[3] + v[4] + v[5] + v[6] + v[7];
    *total += all;
    *busy += all - v[3] - v[4];   /* idle, iowait; steal counts as busy: the core is not ours */
    n++;
  }
  fclose(f);
  return n;
}

/* CPU seconds this process has used so far (all its threads). */
static double own_seconds(void) {
  struct timespec ts;
  if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts) != 0) return -1.0;
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Cores of this process's CPU set kept busy by other work, measured over `ms` milliseconds while
 * this process's main thread sleeps; what this process used meanwhile (OpenMP threads still
 * spinning after a parallel region) is subtracted. *ncpu: the CPUs of the set. Returns the busy
 * cores (0 .. *ncpu), or -1 when /proc/stat, the CPU set or the clocks cannot be read or the
 * counters did not advance consistently (hot-plug, a counter reset). Linux only (-1 elsewhere). */
double tubempm_cores_busy(int ms, int *ncpu) {
  cpu_set_t set;
  unsigned long long b0, t0, b1, t1;
  struct timespec gap, w0, w1;
  double own0, own1, busy, wall;
  *ncpu = 0;
  if (sched_getaffinity(0, sizeof set, &set) != 0) return -1.0;
  own0 = own_seconds();
  if (own0 < 0.0 || clock_gettime(CLOCK_MONOTONIC, &w0) != 0) return -1.0;
  int n = cpu_times(&set, &b0, &t0);
  if (n <= 0) return -1.0;
  gap.tv_sec = ms / 1000;
  gap.tv_nsec = (long)(ms % 1000) * 1000000L;
  nanosleep(&gap, NULL);
  if (cpu_times(&set, &b1, &t1) != n || t1 <= t0 || b1 < b0 || b1 - b0 > t1 - t0) return -1.0;
  own1 = own_seconds();
  if (own1 < own0 || clock_gettime(CLOCK_MONOTONIC, &w1) != 0) return -1.0;
  wall = (double)(w1.tv_sec - w0.tv_sec) + 1e-9 * (double)(w1.tv_nsec - w0.tv_nsec);
  if (wall <= 0.0) return -1.0;
  busy = (double)n * (double)(b1 - b0) / (double)(t1 - t0) - (own1 - own0) / wall;
  *ncpu = n;
  return busy < 0.0 ? 0.0 : (busy > (double)n ? (double)n : busy);
}
#else
double tubempm_cores_busy(int ms, int *ncpu) {
  (void)ms;
  *ncpu = 0;
  return -1.0;
}
#endif
