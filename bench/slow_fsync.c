/* slow_fsync.so: a slow file system's sync for measurements (scripts/daemon-load.sh), the same for
 * any build of inertiald: LD_PRELOAD'ed, it makes every fsync and fdatasync sleep SLOW_FSYNC_MS
 * milliseconds (default 20) before doing the real one. A checkpoint syncs twice (the file, then its
 * directory: estimator_state_file.cpp), so it stalls its thread 2 x SLOW_FSYNC_MS. Not part of the
 * daemon; built by the script with the system's C compiler. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdlib.h>
#include <time.h>

static void Delay(void) {
  const char* env = getenv("SLOW_FSYNC_MS");
  const long ms = env != NULL ? atol(env) : 20;
  struct timespec t = {ms / 1000, (ms % 1000) * 1000000L};
  while (nanosleep(&t, &t) != 0) {
  }
}

int fsync(int fd) {
  static int (*real)(int) = NULL;
  if (real == NULL) real = (int (*)(int))dlsym(RTLD_NEXT, "fsync");
  Delay();
  return real(fd);
}

int fdatasync(int fd) {
  static int (*real)(int) = NULL;
  if (real == NULL) real = (int (*)(int))dlsym(RTLD_NEXT, "fdatasync");
  Delay();
  return real(fd);
}
