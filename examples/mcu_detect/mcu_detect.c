/*
 * mcu_detect -- the library in firmware: one real sonar frame, converted to
 * a const array (flash) at build time (embed_pgm.cmake, from data/ in the
 * repository), detected from a static workspace; prints the same JSON line
 * as the host tool `actag_detect --json --min-range 0.1 --max-range 1.5
 * --aperture-deg 60 FILE` (every field but time_ms, which is the elapsed
 * time of actag_detect on the board's 25 MHz timer).
 *
 * What a firmware needs and what it does not: no heap, no stdio, no libm
 * (the library's sqrt and log need none, src/fpmath.h), no strcmp (the
 * family comes from its direct accessor, actag/families.h), no writable
 * static data in the library; the only RAM is the frame-sized workspace
 * and the stack. The numbers are formatted here exactly as glibc's printf
 * formats them (the binary value rounded half-to-even), so the line can be
 * compared byte for byte with the host's. Output goes through board_puts
 * (semihosting on the QEMU board); a real board would use its UART.
 *
 * Built only in cross builds with cmake/toolchains/cortex-m4.cmake or
 * cortex-m7.cmake; run under qemu-system-arm (test mcu_detect_matches_host).
 *
 * MCU_INPLACE (the mcu_detect_inplace firmware): the frame is first copied
 * into RAM, as a sonar driver's DMA buffer would hold it, and detected with
 * actag_detect_inplace, which filters it in place: the workspace is then
 * ACTAG_WORKSPACE_SIZE_INPLACE (127,392 bytes at 530 x 512, a 128 KiB DTCM)
 * instead of ACTAG_WORKSPACE_SIZE. The line equals the host tool's with
 * --inplace (test mcu_detect_inplace_matches_host).
 */
#include "actag/actag.h"
#include "actag/families.h"
#include "board.h"
#include "mcu_frame.h"

#include <stdint.h>

#ifndef ACTAG_HAVE_AcTag24h10
#error "mcu_detect needs AcTag24h10 in ACTAG_FAMILIES"
#endif

#define MAX_DET 8

#ifdef MCU_INPLACE
static uint8_t workspace[ACTAG_WORKSPACE_SIZE_INPLACE(MCU_FRAME_ROWS, MCU_FRAME_COLS)];
static uint8_t frame_ram[(unsigned long)MCU_FRAME_ROWS * MCU_FRAME_COLS]; /* the "DMA buffer" */
#else
static uint8_t workspace[ACTAG_WORKSPACE_SIZE(MCU_FRAME_ROWS, MCU_FRAME_COLS)];
#endif

/* ------------------------------------------------------------ the board's timer */

/* CMSDK APB timer 0 of the MPS2 boards (25 MHz, counting down). */
#define TIMER0_CTRL (*(volatile uint32_t *)0x40000000u)
#define TIMER0_VALUE (*(volatile uint32_t *)0x40000004u)
#define TIMER0_RELOAD (*(volatile uint32_t *)0x40000008u)
#define TIMER_HZ 25000000u

static void timer_start(void)
{
    TIMER0_CTRL = 0u;
    TIMER0_RELOAD = 0xffffffffu;
    TIMER0_VALUE = 0xffffffffu;
    TIMER0_CTRL = 1u; /* enable */
}

static uint32_t timer_ticks(void) { return 0xffffffffu - TIMER0_VALUE; }

/* ------------------------------------------------------------ output line */

static char line[2048];
static unsigned len;

static void put_s(const char *s)
{
    while (*s != '\0' && len < sizeof line - 1)
        line[len++] = *s++;
}

static void put_u64(uint64_t v, int min_digits)
{
    char t[24];
    int n = 0;
    do {
        t[n++] = (char)('0' + (int)(v % 10u));
        v /= 10u;
    } while (v != 0u || n < min_digits);
    while (n > 0 && len < sizeof line - 1)
        line[len++] = t[--n];
}

static void put_int(int v)
{
    if (v < 0) {
        put_s("-");
        put_u64((uint64_t)(-(int64_t)v), 1);
    } else {
        put_u64((uint64_t)v, 1);
    }
}

/* printf("%.<decimals>f", (double)v) for a finite float: the exact binary
 * value v = m 2^e times 10^decimals, rounded half to even, in integers
 * (|v| < 2^40, decimals <= 6). glibc prints "-0.00" for small negative
 * values, and so does this. */
static void put_fixed(float v, int decimals)
{
    uint32_t u, m;
    int e, i;
    uint64_t p10 = 1u, q;
    union {
        float f;
        uint32_t u;
    } cv;
    cv.f = v;
    u = cv.u;
    if (((u >> 23) & 0xffu) == 0xffu) {
        put_s((u & 0x7fffffu) ? "nan" : (u >> 31) ? "-inf" : "inf");
        return;
    }
    if (u >> 31)
        put_s("-");
    for (i = 0; i < decimals; i++)
        p10 *= 10u;
    e = (int)((u >> 23) & 0xffu);
    m = u & 0x7fffffu;
    if (e == 0)
        e = 1; /* subnormal */
    else
        m |= 0x800000u;
    e -= 150; /* |v| = m * 2^e */
    if (e > 16) {
        put_s("out-of-range"); /* |v| >= 2^40: not a pixel, metre or margin */
        return;
    } else if (e >= 0) {
        q = ((uint64_t)m * p10) << e;
    } else {
        uint64_t prod = (uint64_t)m * p10; /* < 2^44 */
        int s = -e;
        if (s >= 63) {
            q = 0u; /* below half a unit of the last digit */
        } else {
            uint64_t r = prod & (((uint64_t)1 << s) - 1u), half = (uint64_t)1 << (s - 1);
            q = prod >> s;
            if (r > half || (r == half && (q & 1u)))
                q++;
        }
    }
    put_u64(q / p10, 1);
    if (decimals > 0) {
        put_s(".");
        put_u64(q % p10, decimals);
    }
}

/* ------------------------------------------------------------ main */

int main(void)
{
    actag_family fam;
    actag_params params;
    actag_sonar_geometry geo;
    actag_frame frame;
    actag_detection det[MAX_DET];
    actag_stats stats;
    uint32_t t0, t1;
    int n, k, c;

    /* The host tool's defaults and options: actag_params_default(), the
     * family AcTag24h10, --min-range 0.1 --max-range 1.5 --aperture-deg 60
     * (converted as the tool converts them: double, then float). */
    if (actag_family_AcTag24h10(&fam) != ACTAG_OK)
        return 1;
    actag_params_default(&params);
    params.family = &fam;
    geo.min_range = (float)0.1;
    geo.max_range = (float)1.5;
    geo.aperture = (float)(60.0 * 3.14159265358979323846 / 180.0);
    geo.bearings = 0;
    geo.flags = 0u;
#ifdef MCU_INPLACE
    for (k = 0; k < MCU_FRAME_ROWS * MCU_FRAME_COLS; k++)
        frame_ram[k] = mcu_frame[k];
    frame.data = frame_ram;
#else
    frame.data = mcu_frame;
#endif
    frame.rows = MCU_FRAME_ROWS;
    frame.cols = MCU_FRAME_COLS;
    frame.stride = MCU_FRAME_COLS;
    frame.depth = 8;

    timer_start();
    t0 = timer_ticks();
#ifdef MCU_INPLACE
    n = actag_detect_inplace(&frame, &geo, &params, workspace, sizeof workspace, det, MAX_DET,
                             &stats);
#else
    n = actag_detect(&frame, &geo, &params, workspace, sizeof workspace, det, MAX_DET, &stats);
#endif
    t1 = timer_ticks();

    put_s("{\"file\": \"" MCU_FRAME_NAME "\"");
    if (n < 0) {
        put_s(", \"error\": \"");
        put_s(actag_strerror(n));
        put_s("\"}\n");
        line[len] = '\0';
        board_puts(line);
        return 1;
    }
    put_s(", \"rows\": ");
    put_int(frame.rows);
    put_s(", \"cols\": ");
    put_int(frame.cols);
    put_s(", \"detections\": [");
    for (k = 0; k < n; k++) {
        put_s(k ? ", {\"id\": " : "{\"id\": ");
        put_int(det[k].id);
        put_s(", \"hamming\": ");
        put_int(det[k].hamming);
        put_s(", \"decision_margin\": ");
        put_fixed(det[k].decision_margin, 2);
        put_s(det[k].mirrored ? ", \"mirrored\": true" : ", \"mirrored\": false");
        put_s(", \"corners\": [");
        for (c = 0; c < 4; c++) { /* the host tool's keys and digits */
            put_s(c ? ", {\"x_col\": " : "{\"x_col\": ");
            put_fixed(det[k].corners[c].x, 3);
            put_s(", \"y_row\": ");
            put_fixed(det[k].corners[c].y, 3);
            put_s(", \"range_m\": ");
            put_fixed(det[k].range[c], 5);
            put_s(", \"azimuth_rad\": ");
            put_fixed(det[k].azimuth[c], 5);
            put_s("}");
        }
        put_s("]}");
    }
    put_s("], \"time_ms\": ");
    put_fixed((float)(t1 - t0) / (float)(TIMER_HZ / 1000u), 3);
    put_s("}\n");
    line[len] = '\0';
    board_puts(line);
    return stats.dropped > 0 ? 1 : 0;
}
