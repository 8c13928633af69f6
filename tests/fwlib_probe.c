/* A probe of FANUC's FOCAS library: one build for each of its builds (Linux x86-64 with gcc,
 * Windows Fwlib32.dll with mingw-w64 under wine), the same calls, the raw bytes each call
 * fills. tests/test_fwlib_windows.py compares the two outputs line by line.
 *
 * usage: fwlib_probe HOST PORT [SLOTS]
 * output: one line per call, "name return-code hex-bytes-of-what-it-filled" (counts and other
 * values returned through pointers on lines of their own). SLOTS is the number of values an
 * all-axes offset read makes room for (the path's axes at 16i class, the open answer's max
 * axes at 30i class; 32 when not given).
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
/* spindles and servo figures */
extern short API cnc_rdspmeter(u16 h, short type, short *count, void *out);
extern short API cnc_rdspdlname(u16 h, short *count, void *out);
extern short API cnc_rdspeed(u16 h, short type, void *out);
extern short API cnc_acts2(u16 h, short spindle, void *out);
extern short API cnc_rdspmaxrpm(u16 h, short spindle, void *out);
extern short API cnc_rdspgear(u16 h, short spindle, void *out);
extern short API cnc_rdcurrent(u16 h, void *out);
extern short API cnc_rdsrvspeed(u16 h, void *out);
extern short API cnc_rdloopgain(u16 h, void *out);
extern short API cnc_getfigure(u16 h, short type, short *valid, short *in, short *out);
/* modal data, commands, messages, execution pointers */
extern short API cnc_modal(u16 h, short type, short block, void *out);
extern short API cnc_rdgcode(u16 h, short type, short block, short *count, void *out);
extern short API cnc_rdcommand(u16 h, short type, short block, short *count, void *out);
extern short API cnc_rdopmsg(u16 h, short type, short length, void *out);
extern short API cnc_exeprgname2(u16 h, char *out);
extern short API cnc_rdactpt(u16 h, int32_t *program, int32_t *block);
extern short API cnc_rdblkcount(u16 h, int32_t *count);
extern short API cnc_rdmdipntr(u16 h, void *out);
/* offsets and tool life */
extern short API cnc_rdtofs(u16 h, short number, short type, short length, void *out);
extern short API cnc_rdtofsr(u16 h, short first, short type, short last, short length, void *out);
extern short API cnc_rdzofs(u16 h, short number, short axis, short length, void *out);
extern short API cnc_rdzofsr(u16 h, short first, short axis, short last, short length, void *out);
extern short API cnc_toolnum(u16 h, short group, short tool, void *out);
extern short API cnc_rdntool(u16 h, short group, void *out);
extern short API cnc_rdlife(u16 h, short group, void *out);
extern short API cnc_rdcount(u16 h, short group, void *out);
extern short API cnc_rdtoolgrp(u16 h, short group, short length, void *out);
extern short API cnc_rdtlinfo(u16 h, void *out);
/* the control's information */
extern short API cnc_statinfo2(u16 h, void *out);
extern short API cnc_rdsyssoft(u16 h, void *out);
extern short API cnc_rddiagnum(u16 h, void *out);
extern short API cnc_rddiaginfo(u16 h, short first, u16 count, void *out);
extern short API cnc_rdparanum(u16 h, void *out);
extern short API cnc_rdset(u16 h, short number, short axis, short length, void *out);
extern short API cnc_rdsetinfo(u16 h, short first, u16 count, void *out);
extern short API pmc_rdpmcinfo(u16 h, short type, void *out);
extern short API pmc_rdpmctitle(u16 h, void *out);
extern short API cnc_rdopnlsgnl(u16 h, short select, void *out);
extern short API cnc_gettimer(u16 h, void *inout);
extern short API cnc_rdetherinfo(u16 h, short *type, short *device);
extern short API cnc_rdprstrinfo(u16 h, void *out);
/* the 30i file system */
extern short API cnc_rdpdf_drive(u16 h, void *out);
extern short API cnc_rdpdf_curdir(u16 h, short type, char *out);
extern short API cnc_rdpdf_subdir(u16 h, short *count, void *in, void *out);
extern short API cnc_rdpdf_alldir(u16 h, short *count, void *in, void *out);
extern short API cnc_rdpdf_inf(u16 h, char *path, short type, void *out);

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

/* a call that fills a count and a buffer: the count on a line, then the bytes (the call is
 * made before: C leaves the order in which arguments are evaluated open) */
static void counted(const char *name, short rc, short count, size_t each) {
  printf("%s count %d\n", name, count);
  dump(name, rc, buf, each * (size_t)(count > 0 && count <= 64 ? count : 0));
}

/* the path and numbers of the 30i file system's folder requests (IDBPDFSDIR, IDBPDFADIR) */
static void folder_request(const char *path, short a, short b, short c) {
  CLEAR();
  strncpy((char *)buf, path, 211);
  memcpy(buf + 212, &a, 2);
  memcpy(buf + 214, &b, 2);
  memcpy(buf + 216, &c, 2);
}

static void probe_more(u16 h, short slots);

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
  probe_more(h, argc > 3 ? (short)atoi(argv[3]) : 32);
  printf("cnc_freelibhndl %d\n", cnc_freelibhndl(h));
  return 0;
}

/* The functions collectors call besides the older ones: spindles, servo figures, modal data,
 * messages, offsets, tool life, the control's information, the clock and the file system. */
static void probe_more(u16 h, short slots) {
  char name[64];
  short a, b, c, rc;
  int32_t l1, l2;
  /* spindles: the meters (load, speed, both), names, speeds, figures by selector */
  for (short kind = -1; kind <= 1; kind++) {
    CLEAR(); a = 8; snprintf(name, sizeof name, "cnc_rdspmeter(%d)", kind);
    rc = cnc_rdspmeter(h, kind, &a, buf);
    counted(name, rc, a, 24);
  }
  CLEAR(); a = 8; rc = cnc_rdspdlname(h, &a, buf);
    counted("cnc_rdspdlname", rc, a, 4);
  for (short kind = -1; kind <= 1; kind++) {
    CLEAR(); snprintf(name, sizeof name, "cnc_rdspeed(%d)", kind);
    dump(name, cnc_rdspeed(h, kind, buf), buf, 24);
  }
  for (short sp = -1; sp <= 1; sp += 2) {
    CLEAR(); snprintf(name, sizeof name, "cnc_acts2(%d)", sp);
    dump(name, cnc_acts2(h, sp, buf), buf, 4 + 4 * 8);
    CLEAR(); snprintf(name, sizeof name, "cnc_rdspmaxrpm(%d)", sp);
    dump(name, cnc_rdspmaxrpm(h, sp, buf), buf, 4 + 2 * 8);
    CLEAR(); snprintf(name, sizeof name, "cnc_rdspgear(%d)", sp);
    dump(name, cnc_rdspgear(h, sp, buf), buf, 4 + 2 * 8);
    CLEAR(); snprintf(name, sizeof name, "cnc_rdspload(%d)", sp);
    dump(name, cnc_rdspload(h, sp, buf), buf, 4 + 2 * 8);
  }
  CLEAR(); dump("cnc_rdcurrent", cnc_rdcurrent(h, buf), buf, 2 * 32);
  CLEAR(); dump("cnc_rdsrvspeed", cnc_rdsrvspeed(h, buf), buf, 4 * 32);
  CLEAR(); dump("cnc_rdloopgain", cnc_rdloopgain(h, buf), buf, 4 * 32);
  for (short kind = 0; kind <= 1; kind++) {
    short in[32], out[32];
    memset(in, 0, sizeof in); memset(out, 0, sizeof out); a = 0;
    rc = cnc_getfigure(h, kind, &a, in, out);
    snprintf(name, sizeof name, "cnc_getfigure(%d)", kind);
    printf("%s valid %d\n", name, rc == 0 ? a : 0);
    memcpy(buf, in, sizeof in); memcpy(buf + sizeof in, out, sizeof out);
    dump(name, rc, buf, sizeof in + sizeof out);
  }
  /* modal data: all G groups, one group, the other data (all, F, S, T), the axes' data,
     of the block being run and of the next one */
  static const short modal[] = {-1, 0, 2, 13, -2, 103, 107, 108, -3, 200, 201, 127, -4};
  for (short block = 0; block <= 1; block++)
    for (size_t i = 0; i < sizeof modal / sizeof *modal; i++) {
      CLEAR(); snprintf(name, sizeof name, "cnc_modal(%d,%d)", modal[i], block);
      dump(name, cnc_modal(h, modal[i], block, buf), buf, 4 + 8 * 32);
    }
  for (short block = 0; block <= 1; block++) {
    CLEAR(); a = 40; snprintf(name, sizeof name, "cnc_rdgcode(-1,%d)", block);
    rc = cnc_rdgcode(h, -1, block, &a, buf);
    counted(name, rc, a, 12);
    CLEAR(); a = 1; snprintf(name, sizeof name, "cnc_rdgcode(0,%d)", block);
    rc = cnc_rdgcode(h, 0, block, &a, buf);
    counted(name, rc, a, 12);
    CLEAR(); a = 30; snprintf(name, sizeof name, "cnc_rdcommand(-1,%d)", block);
    rc = cnc_rdcommand(h, -1, block, &a, buf);
    counted(name, rc, a, 12);
  }
  CLEAR(); dump("cnc_rdopmsg(0)", cnc_rdopmsg(h, 0, 6 + 256, buf), buf, 6 + 256);
  CLEAR(); dump("cnc_rdopmsg(0,70)", cnc_rdopmsg(h, 0, 6 + 64, buf), buf, 6 + 64);
  CLEAR(); dump("cnc_exeprgname2", cnc_exeprgname2(h, (char *)buf), buf, 256);
  l1 = l2 = 0; a = cnc_rdactpt(h, &l1, &l2);
  printf("cnc_rdactpt %d %d %d\n", a, (int)l1, (int)l2);
  l1 = 0; a = cnc_rdblkcount(h, &l1); printf("cnc_rdblkcount %d %d\n", a, (int)l1);
  CLEAR(); dump("cnc_rdmdipntr", cnc_rdmdipntr(h, buf), buf, 16);
  /* tool offsets (each type of offset 1, a range), work offsets (one, all axes, a range) */
  for (short type = 0; type <= 3; type++) {
    CLEAR(); snprintf(name, sizeof name, "cnc_rdtofs(1,%d)", type);
    dump(name, cnc_rdtofs(h, 1, type, 8, buf), buf, 8);
  }
  CLEAR(); dump("cnc_rdtofsr(1,-1,3)", cnc_rdtofsr(h, 1, -1, 3, 8 + 4 * 12, buf), buf, 8 + 4 * 12);
  CLEAR(); dump("cnc_rdtofsr(1,0,2)", cnc_rdtofsr(h, 1, 0, 2, 8 + 4 * 2, buf), buf, 8 + 4 * 2);
  for (short number = 0; number <= 2; number++) {
    CLEAR(); snprintf(name, sizeof name, "cnc_rdzofs(%d,-1)", number);
    dump(name, cnc_rdzofs(h, number, -1, 4 + 4 * slots, buf), buf, 4 + 4 * 32);
  }
  CLEAR(); dump("cnc_rdzofs(1,2)", cnc_rdzofs(h, 1, 2, 8, buf), buf, 8);
  CLEAR(); dump("cnc_rdzofsr(0,2,6)", cnc_rdzofsr(h, 0, 2, 6, 8 + 4 * 7, buf), buf, 8 + 4 * 7);
  CLEAR(); dump("cnc_rdzofsr(1,-1,2)", cnc_rdzofsr(h, 1, -1, 2, 8 + 4 * 2 * slots, buf), buf,
                8 + 4 * 2 * slots);
  /* tool life: groups 1 and 2, the first tools, an undeclared group */
  for (short group = 1; group <= 3; group++) {
    CLEAR(); snprintf(name, sizeof name, "cnc_rdntool(%d)", group);
    dump(name, cnc_rdntool(h, group, buf), buf, 8);
    CLEAR(); snprintf(name, sizeof name, "cnc_rdlife(%d)", group);
    dump(name, cnc_rdlife(h, group, buf), buf, 8);
    CLEAR(); snprintf(name, sizeof name, "cnc_rdcount(%d)", group);
    dump(name, cnc_rdcount(h, group, buf), buf, 8);
    CLEAR(); snprintf(name, sizeof name, "cnc_toolnum(%d,1)", group);
    dump(name, cnc_toolnum(h, group, 1, buf), buf, 8);
    CLEAR(); snprintf(name, sizeof name, "cnc_rdtoolgrp(%d)", group);
    dump(name, cnc_rdtoolgrp(h, group, 20 + 20 * 2, buf), buf, 20 + 20 * 2);
  }
  CLEAR(); dump("cnc_rdtlinfo", cnc_rdtlinfo(h, buf), buf, 16);
  /* the control's information */
  CLEAR(); dump("cnc_statinfo2", cnc_statinfo2(h, buf), buf, 26);
  CLEAR(); dump("cnc_rdsyssoft", cnc_rdsyssoft(h, buf), buf, 548);
  CLEAR(); dump("cnc_rddiagnum", cnc_rddiagnum(h, buf), buf, 6);
  CLEAR(); dump("cnc_rddiaginfo(0,10)", cnc_rddiaginfo(h, 0, 10, buf), buf, 6 + 4 * 10);
  CLEAR(); dump("cnc_rdparanum", cnc_rdparanum(h, buf), buf, 6);
  CLEAR(); dump("cnc_rdsetinfo(0,10)", cnc_rdsetinfo(h, 0, 10, buf), buf, 6 + 4 * 10);
  CLEAR(); dump("cnc_rdset(20)", cnc_rdset(h, 20, 0, 5, buf), buf, 8);
  CLEAR(); dump("cnc_rdset(1320)", cnc_rdset(h, 1320, 0, 8, buf), buf, 8);
  CLEAR(); dump("pmc_rdpmcinfo(-1)", pmc_rdpmcinfo(h, -1, buf), buf, 2 + 6 * 64);
  CLEAR(); dump("pmc_rdpmctitle", pmc_rdpmctitle(h, buf), buf, 380);
  CLEAR(); dump("cnc_rdopnlsgnl", cnc_rdopnlsgnl(h, 0x1FFF, buf), buf, 30);
  CLEAR(); a = b = -1; c = cnc_rdetherinfo(h, &a, &b);
  printf("cnc_rdetherinfo %d %d %d\n", c, a, b);
  CLEAR(); dump("cnc_rdprstrinfo", cnc_rdprstrinfo(h, buf), buf, 432);
  /* the clock: the date, the time, #3011/#3012, the run-time parameters */
  for (short type = 0; type <= 2; type++) {
    CLEAR(); memcpy(buf, &type, 2); snprintf(name, sizeof name, "cnc_gettimer(%d)", type);
    dump(name, cnc_gettimer(h, buf), buf, 10);
  }
  for (short number = 3011; number <= 3012; number++) {
    CLEAR(); snprintf(name, sizeof name, "cnc_rdmacro(%d)", number);
    dump(name, cnc_rdmacro(h, number, 10, buf), buf, 10);
  }
  for (short number = 6750; number <= 6758; number++) {
    CLEAR(); snprintf(name, sizeof name, "cnc_rdparam(%d,0)", number);
    dump(name, cnc_rdparam(h, number, 0, 8, buf), buf, 8);
  }
  CLEAR(); dump("cnc_diagnoss(4901,-1)", cnc_diagnoss(h, 4901, -1, 4 + 4 * slots, buf), buf,
                4 + 4 * 32);
  CLEAR(); dump("cnc_diagnoss(4901,1)", cnc_diagnoss(h, 4901, 1, 8, buf), buf, 8);
  /* the 30i file system */
  CLEAR(); dump("cnc_rdpdf_drive", cnc_rdpdf_drive(h, buf), buf, 4 + 12 * 16);
  for (short type = 1; type <= 2; type++) {
    CLEAR(); snprintf(name, sizeof name, "cnc_rdpdf_curdir(%d)", type);
    dump(name, cnc_rdpdf_curdir(h, type, (char *)buf), buf, 256);
  }
  static const char *folders[] = {"//CNC_MEM/", "//CNC_MEM/USER/", "//CNC_MEM/USER/PATH1/"};
  for (size_t i = 0; i < sizeof folders / sizeof *folders; i++) {
    static unsigned char request[256];
    folder_request(folders[i], 0, 0, 0);
    memcpy(request, buf, sizeof request);
    CLEAR(); a = 8; snprintf(name, sizeof name, "cnc_rdpdf_subdir(%s)", folders[i]);
    rc = cnc_rdpdf_subdir(h, &a, request, buf);
    counted(name, rc, a, 40);
    folder_request(folders[i], 0, 1, 1);
    memcpy(request, buf, sizeof request);
    CLEAR(); a = 20; snprintf(name, sizeof name, "cnc_rdpdf_alldir(%s)", folders[i]);
    rc = cnc_rdpdf_alldir(h, &a, request, buf);
    counted(name, rc, a, 128);
    for (short type = 0; type <= 1; type++) {
      char path[64];
      strncpy(path, folders[i], sizeof path - 1);
      path[sizeof path - 1] = 0;
      CLEAR(); snprintf(name, sizeof name, "cnc_rdpdf_inf(%s,%d)", folders[i], type);
      dump(name, cnc_rdpdf_inf(h, path, type, buf), buf, 16);
    }
  }
}
