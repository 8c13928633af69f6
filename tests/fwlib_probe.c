/* A probe of FANUC's FOCAS library: one build for each of its builds (Linux x86-64 with gcc,
 * Windows Fwlib32.dll with mingw-w64 under wine), the same calls, the raw bytes each call
 * fills. tests/test_fwlib_windows.py compares the two outputs line by line.
 *
 * usage: fwlib_probe HOST PORT
 * output: one line per call, "name return-code hex-bytes-of-what-it-filled".
 *
 * The functions are declared here with fixed-width types, not through FANUC's header: both
 * libraries lay FOCAS `long` fields out as 4 bytes (the header's `long` is 8 bytes to gcc on
 * x86-64), and every result is dumped as the library's bytes, so the two builds print the same
 * lines when the libraries behave the same.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef _WIN32
#define API __stdcall
#else
#define API
#endif

typedef unsigned short u16;

extern short API cnc_allclibhndl3(const char *host, u16 port, int32_t timeout, u16 *handle);
extern short API cnc_freelibhndl(u16 h);
extern short API cnc_sysinfo(u16 h, void *out);
extern short API cnc_statinfo(u16 h, void *out);
extern short API cnc_getpath(u16 h, short *path, short *maxpath);
extern short API cnc_rdcncid(u16 h, void *out);
extern short API cnc_rdmacro(u16 h, short number, short length, void *out);
extern short API cnc_rdmacror2(u16 h, uint32_t first, uint32_t *count, double *out);
extern short API cnc_rdparam(u16 h, short number, short axis, short length, void *out);
extern short API cnc_diagnoss(u16 h, short number, short axis, short length, void *out);
extern short API pmc_rdpmcrng(u16 h, short area, short type, u16 first, u16 last, u16 length,
                              void *out);
extern short API cnc_alarm2(u16 h, int32_t *out);
extern short API cnc_rdalmmsg2(u16 h, short type, short *count, void *out);
extern short API cnc_rdprgnum(u16 h, void *out);
extern short API cnc_exeprgname(u16 h, void *out);
extern short API cnc_rdseqnum(u16 h, void *out);
extern short API cnc_actf(u16 h, void *out);
extern short API cnc_acts(u16 h, void *out);
extern short API cnc_absolute(u16 h, short axis, short length, void *out);
extern short API cnc_machine(u16 h, short axis, short length, void *out);
extern short API cnc_relative(u16 h, short axis, short length, void *out);
extern short API cnc_distance(u16 h, short axis, short length, void *out);
extern short API cnc_rdposition(u16 h, short type, short *count, void *out);
extern short API cnc_rddynamic2(u16 h, short axis, short length, void *out);
extern short API cnc_rdspload(u16 h, short spindle, void *out);
extern short API cnc_rdsvmeter(u16 h, short *count, void *out);
extern short API cnc_rdtimer(u16 h, short type, void *out);
extern short API cnc_rdalmhistry(u16 h, u16 first, u16 last, u16 length, void *out);
extern short API cnc_rdaxisname(u16 h, short *count, void *out);

static unsigned char buf[8192];

static void dump(const char *name, short rc, const void *data, size_t size) {
  const unsigned char *p = (const unsigned char *)data;
  printf("%s %d ", name, rc);
  if (rc == 0)
    for (size_t i = 0; i < size; i++) printf("%02x", p[i]);
  printf("\n");
  fflush(stdout);
}

#define CLEAR() memset(buf, 0, sizeof buf)

int main(int argc, char **argv) {
  if (argc < 3) {
    fprintf(stderr, "usage: fwlib_probe HOST PORT\n");
    return 2;
  }
#ifndef _WIN32
  extern short cnc_startupprocess(long level, const char *log);
  const char *log = getenv("FOCAS_NET_FWLIB_LOG");
  cnc_startupprocess(log ? 3 : 0, log ? log : "/dev/null");
#endif
  u16 h = 0;
  short rc = cnc_allclibhndl3(argv[1], (u16)atoi(argv[2]), 3, &h);
  printf("cnc_allclibhndl3 %d\n", rc);
  if (rc != 0) return 1;
  char name[64];
  short a, b;
  int32_t alarm;

  CLEAR(); dump("cnc_sysinfo", cnc_sysinfo(h, buf), buf, 18);
  CLEAR(); dump("cnc_statinfo", cnc_statinfo(h, buf), buf, 18);
  a = b = 0; rc = cnc_getpath(h, &a, &b); printf("cnc_getpath %d %d %d\n", rc, a, b);
  CLEAR(); dump("cnc_rdcncid", cnc_rdcncid(h, buf), buf, 16);
  static const short macros[] = {100, 101, 500, 3901, 4120};
  for (size_t i = 0; i < sizeof macros / sizeof *macros; i++) {
    CLEAR(); snprintf(name, sizeof name, "cnc_rdmacro(%d)", macros[i]);
    dump(name, cnc_rdmacro(h, macros[i], 10, buf), buf, 10);
  }
  double doubles[3] = {0, 0, 0};
  uint32_t count = 3;
  dump("cnc_rdmacror2(500)", cnc_rdmacror2(h, 500, &count, doubles), doubles, sizeof doubles);
  /* all-axes reads with the room a 30i-class CNC of 32 axes needs (4 + 8 * 32) */
  static const short params[][2] = {{20, 0}, {1320, -1}, {1320, 2}, {1825, -1}, {6711, 0}};
  for (size_t i = 0; i < sizeof params / sizeof *params; i++) {
    CLEAR(); snprintf(name, sizeof name, "cnc_rdparam(%d,%d)", params[i][0], params[i][1]);
    dump(name, cnc_rdparam(h, params[i][0], params[i][1], 4 + 8 * 32, buf), buf, 4 + 8 * 32);
  }
  CLEAR(); dump("cnc_diagnoss(300,-1)", cnc_diagnoss(h, 300, -1, 4 + 8 * 32, buf), buf, 4 + 8 * 32);
  CLEAR(); dump("pmc_rdpmcrng(G,0,0..15)", pmc_rdpmcrng(h, 0, 0, 0, 15, 8 + 16, buf), buf, 24);
  CLEAR(); dump("pmc_rdpmcrng(R,1,100..107)", pmc_rdpmcrng(h, 5, 1, 100, 107, 16, buf), buf, 16);
  alarm = 0; rc = cnc_alarm2(h, &alarm); printf("cnc_alarm2 %d %d\n", rc, (int)alarm);
  CLEAR(); a = 10; rc = cnc_rdalmmsg2(h, -1, &a, buf);
  printf("cnc_rdalmmsg2 count %d\n", a); dump("cnc_rdalmmsg2", rc, buf, 76 * 10);
  CLEAR(); dump("cnc_rdprgnum", cnc_rdprgnum(h, buf), buf, 8);
  CLEAR(); dump("cnc_exeprgname", cnc_exeprgname(h, buf), buf, 40);
  CLEAR(); dump("cnc_rdseqnum", cnc_rdseqnum(h, buf), buf, 8);
  CLEAR(); dump("cnc_actf", cnc_actf(h, buf), buf, 8);
  CLEAR(); dump("cnc_acts", cnc_acts(h, buf), buf, 8);
  CLEAR(); dump("cnc_absolute(-1)", cnc_absolute(h, -1, 4 + 4 * 32, buf), buf, 4 + 4 * 32);
  CLEAR(); dump("cnc_machine(-1)", cnc_machine(h, -1, 4 + 4 * 32, buf), buf, 4 + 4 * 32);
  CLEAR(); dump("cnc_relative(2)", cnc_relative(h, 2, 8, buf), buf, 8);
  CLEAR(); dump("cnc_distance(-1)", cnc_distance(h, -1, 4 + 4 * 32, buf), buf, 4 + 4 * 32);
  CLEAR(); a = 8; rc = cnc_rdposition(h, -1, &a, buf);
  printf("cnc_rdposition count %d\n", a); dump("cnc_rdposition", rc, buf, 48 * 8);
  CLEAR(); dump("cnc_rddynamic2(-1)", cnc_rddynamic2(h, -1, 28 + 16 * 32, buf), buf, 28 + 16 * 32);
  CLEAR(); dump("cnc_rddynamic2(1)", cnc_rddynamic2(h, 1, 44, buf), buf, 44);
  CLEAR(); dump("cnc_rdspload(-1)", cnc_rdspload(h, -1, buf), buf, 4 + 2 * 8);
  CLEAR(); a = 8; rc = cnc_rdsvmeter(h, &a, buf);
  printf("cnc_rdsvmeter count %d\n", a); dump("cnc_rdsvmeter", rc, buf, 12 * 8);
  CLEAR(); a = 8; rc = cnc_rdaxisname(h, &a, buf);
  printf("cnc_rdaxisname count %d\n", a); dump("cnc_rdaxisname", rc, buf, 4 * 8);
  CLEAR(); dump("cnc_rdtimer(0)", cnc_rdtimer(h, 0, buf), buf, 8);
  CLEAR(); dump("cnc_rdalmhistry(1,2)", cnc_rdalmhistry(h, 1, 2, 6 + 48 * 2, buf), buf, 6 + 48 * 2);
  printf("cnc_freelibhndl %d\n", cnc_freelibhndl(h));
  return 0;
}
