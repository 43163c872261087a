/*
 * hostio.h -- the host tools' shared I/O: files, PGM frames, numbers.
 *
 * MANUAL
 *   Host-only helpers (stdio, malloc) for actag's command-line tools, tests
 *   and benchmarks, so that every tool reads and writes frames and parses
 *   numbers the same way and reports errors the same way. Not part of the
 *   core library (which never allocates).
 *
 *   Errors: every function that can fail returns HOSTIO_OK (0) or -1 and
 *   then writes a one-line message into the caller's `err` buffer (which may
 *   be NULL), naming the file or option and the value at fault, e.g.
 *       "f.pgm: PGM maxval 0 outside 1..65535"
 *       "--max-range: must be a finite number > 0 (got -1)"
 *
 *   Files (the path "-" reads standard input)
 *     hostio_slurp(path, &len, err)        whole file, malloc'd, NUL-terminated
 *                                           (at most HOSTIO_MAX_FILE bytes)
 *     hostio_slurp_text(path, &len, err)   the same for a text file: a NUL byte
 *                                           in it is an error (naming its offset),
 *                                           not the silent end of the text
 *     hostio_write_file(path, data, n, err)  the writers remove what they
 *                                           wrote when writing fails
 *     hostio_remove_partial(path)          removes a regular file a failed write
 *                                           left (links, devices, FIFOs and "-"
 *                                           are kept)
 *     hostio_mkdirs(path, err)             creates a folder and its parents
 *                                           (like mkdir -p; fine when it exists)
 *     hostio_same_file(a, b)               1 when the two paths name one file
 *                                           (the same file found by both, the
 *                                           same string, or, when neither exists
 *                                           yet, the same name in the same
 *                                           folder), else 0: an output must not
 *                                           overwrite an input or another output
 *   Output guard (a tool's output file: none is left half-written by a
 *   failed run; a device, a link or standard output is never removed)
 *     hostio_out_open(&out, path, mode, err)  fopen (NULL path: standard
 *                                           output); only a "w" mode's file
 *                                           is ever removed
 *     hostio_out_close(&out, err)          flushes and closes, checking each
 *                                           step; a failure removes the file
 *     hostio_out_abandon(&out)             closes and removes the file of a
 *                                           run that fails (a tool's die())
 *     out.why                              errno of a failed open or close,
 *                                           for tools with their own wording
 *   PGM (binary P5, 8 or 16 bit; 16-bit samples big-endian as the format says)
 *     hostio_pgm_parse(buf, len, &view, err)  parses a buffer in place, no
 *                                           allocation (usable on bare metal):
 *                                           view.pixels points into buf; one
 *                                           frame: bytes after it are an error;
 *                                           '#' comments in the header, also
 *                                           right after maxval (as Netpbm: its
 *                                           end of line is then the single
 *                                           whitespace before the pixels)
 *     hostio_pgm_read(path, &img, err)     reads a file into a malloc'd image
 *                                           (16-bit samples in host order;
 *                                           samples checked against maxval and
 *                                           8-bit ones scaled as
 *                                           hostio_frame_read does)
 *     hostio_pgm_write(path, &img, err)    writes an image (depth 8 or 16)
 *     hostio_pgm_fwrite(stream, name, &img, err)  the same to an open stream
 *                                           (e.g. stdout); name labels messages
 *     hostio_image_free(&img)
 *     hostio_image_frame(&img, &frame)     the image as the library's
 *                                           actag_frame (no copy)
 *     hostio_ppm_write(path, rgb, rows, cols, err)  a colour picture (P6,
 *                                           rows x cols RGB triplets)
 *   Frames (sonar tools: PGM by its magic, else headerless raw)
 *     hostio_frame_read(path, &raw, &img, err)  a P5 PGM, or a raw frame laid
 *                                           out as raw says (rows x stride
 *                                           samples, 16-bit little-endian; the
 *                                           last row's padding may be absent);
 *                                           raw may be NULL (PGM only)
 *     hostio_frame_parse(buf, len, name, &raw, &img, err)  the same on a
 *                                           buffer in memory
 *     hostio_frame_name(path)              "stdin" for "-", else path
 *   Numbers (the whole string must be the number; ranges are inclusive),
 *   in decimal: an optional '-', digits with an optional point and exponent
 *   ("5", "-5", "0.5", ".5", "5.", "1e-3"); no leading whitespace, '+' sign,
 *   hexadecimal ("0x10", "0x1p-3"), inf or nan (u32: no sign at all; list:
 *   a '+' sign is taken, whitespace separates). A number beyond the type
 *   (an integer past long or 64 bits, a double below the smallest normal
 *   one other than 0) is reported as out of range, not as malformed
 *     hostio_parse_double(name, s, lo, hi, &v, err)
 *     hostio_parse_long(name, s, lo, hi, &v, err)
 *     hostio_parse_doubles(name, s, sep, out, n, err)  exactly n numbers
 *     hostio_parse_list(name, s, out, cap, &n, err)  up to cap finite numbers
 *                                           separated by whitespace or commas
 *                                           (e.g. a file's text); *n is the count
 *                                           (cap + 1 when there were more)
 *   Library error details (actag_error_detail from actag_check and the
 *   validators, actag/common.h) in the tool's own option names
 *     hostio_detail_message(&detail, map, nmap, err)
 *         map[] pairs library fields with options ({"tag_size", "--tag-size"});
 *         err gets "--tag-size: must be a finite number > 0 (metres) (got 0)",
 *         "--min-range/--max-range: must be below --max-range (got 2, limit 1.5)"
 *         or "--bearings b.txt: value 7 must be below the previous bearing
 *         (...) (got 0.3 after 0.29)"; field names inside the rule are
 *         translated too, unmapped ones are printed as the library names them
 *   Bearing tables (actag_detect and actag-sim --bearings: one bearing per
 *   column in radians, in hostio_parse_list's format)
 *     hostio_parse_bearings(name, text, cols, cols_opt, out, err)  exactly
 *                                           cols finite numbers into out (as
 *                                           floats); another count is an error
 *                                           naming the file ("name: bearing
 *                                           table has 49 values, the frame has
 *                                           50 columns", or "..., --cols is 50"
 *                                           when cols_opt is "--cols")
 *     hostio_read_bearings(path, cols, cols_opt, out, err)  the same read from
 *                                           a file (hostio_slurp_text)
 *   Folders (host only: not in the emulated suites' build)
 *     hostio_list_dir(dir, prefix, suffix, &n, err)  "DIR/NAME" for each entry
 *                                           whose name starts with prefix, ends
 *                                           with suffix and is longer than both,
 *                                           sorted (strcmp); malloc'd, freed with
 *                                           hostio_list_free; NULL and a message
 *                                           ("cannot open folder 'DIR': REASON")
 *                                           when it cannot be read; *n may be 0
 *     hostio_list_free(names, n)
 *   Family code lists (the published AcTag<N>h<H>.txt format, actag-familygen
 *   --format txt: '#' comment lines, blank lines, one code per line in ID
 *   order as 0x-prefixed hexadecimal)
 *     hostio_read_codes(path, codes, cap, &n, err)  at most cap codes
 *   JSON output
 *     hostio_json_string(stream, s)  s as a JSON string literal, quotes
 *                            included ('"' and '\\' escaped, control
 *                            characters as \u00XX, UTF-8 as it is, every
 *                            byte that is not well-formed UTF-8 (a file
 *                            name's) as \ufffd, so the output is JSON)
 *     hostio_json_num(buf, fmt, v, have)  v printed with fmt into buf
 *                            (HOSTIO_JNUM_LEN bytes), or "null" when have is
 *                            0 (a rate or median of nothing is no 0);
 *                            returns buf or the literal "null"
 *   Subprocesses
 *     hostio_run(cmd, err)   runs a shell command line (system()); returns its
 *                            exit status 0..255, or -1 (and a message) when it
 *                            could not run or was ended by a signal
 *   Command-line tools (print "PROG: message" on stderr and exit with status 2)
 *     hostio_die(prog, msg)
 *     hostio_stdout_check(prog)          a tool's last step: standard output
 *                                           flushed, and a write error (a full
 *                                           disk, a closed pipe) dies with
 *                                           "standard output: write error"
 *     hostio_opt_double(prog, name, s, lo, hi)   hostio_parse_double or die
 *     hostio_opt_long(prog, name, s, lo, hi)     hostio_parse_long or die
 *     hostio_opt_u32(prog, name, s, lo, hi)      hostio_parse_u32 or die (seeds:
 *                            0..4294967295 whatever the width of long)
 *     hostio_opt_mkdirs(prog, name, path)  hostio_mkdirs or die ("name: ...")
 *     hostio_opt_value(prog, argc, argv, &i)  the value after option argv[i]
 *                                           (i moves onto it), or die
 *                                           ("OPT: missing value")
 *     hostio_opt_unknown(prog, opt)        die ("unknown option 'OPT' (try --help)")
 */
#ifndef ACTAG_HOSTIO_H
#define ACTAG_HOSTIO_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

#define HOSTIO_OK 0
#define HOSTIO_ERRLEN 256 /* a good size for err buffers */
/* Largest file hostio_slurp (and so every reader here) takes, bytes: far
 * above any frame (a 16-bit 8192 x 8192 PGM is 128 MiB), and a bound on
 * what reading /dev/zero or a runaway pipe can cost. */
#define HOSTIO_MAX_FILE (512ul * 1024ul * 1024ul)

/* A frame in memory: rows x cols pixels, row stride in pixels. */
typedef struct hostio_image {
    void *data;   /* uint8_t (depth 8) or uint16_t (depth 16), owned when from _read */
    int rows;
    int cols;
    int stride;   /* pixels */
    int depth;    /* 8 or 16 */
    int maxval;   /* PGM maxval (255 or 65535 for images written by us) */
} hostio_image;

/* A parsed PGM inside the caller's buffer. */
typedef struct hostio_pgm_view {
    const uint8_t *pixels; /* first sample byte inside the buffer */
    int rows, cols;
    int maxval;            /* 1..65535 */
    int bytes_per_sample;  /* 1 (maxval <= 255) or 2 */
} hostio_pgm_view;

/* How a raw (headerless) frame is laid out. */
typedef struct hostio_raw_spec {
    int rows, cols; /* both > 0 to accept raw frames */
    int depth;      /* 8 or 16 (16: little-endian samples) */
    int stride;     /* samples from one row to the next; 0 = cols */
} hostio_raw_spec;

/* Whole file ("-": standard input), malloc'd with a terminating NUL (not counted in *len). */
uint8_t *hostio_slurp(const char *path, size_t *len, char *err);
char *hostio_slurp_text(const char *path, size_t *len, char *err);
int hostio_write_file(const char *path, const void *data, size_t n, char *err);
/* After a failed write: removes path if it is itself a regular file (not
 * "-", a symbolic link, a device or a FIFO), so that no half-written output
 * is left behind. */
void hostio_remove_partial(const char *path);
int hostio_mkdirs(const char *path, char *err);
int hostio_same_file(const char *a, const char *b);

/* An output file being written, removed again when its run fails. Only a
 * regular file that the path itself named when it was opened is removed
 * (what this run created or truncated): never a device (/dev/null,
 * /dev/full), a symbolic link (/dev/stdout) or standard output.
 *   - open: fopen(path, mode); a NULL path is standard output (never closed
 *     or removed). Error "PATH: cannot write: REASON".
 *   - close: fflush, the stream's error flag and fclose; any failure removes
 *     the file and gives "PATH: write error" ("standard output: ...").
 *   - abandon: for a run that fails while the file is open (a tool's die()):
 *     closes it unchecked and removes it.
 * After close or abandon the guard is idle: closing or abandoning it again
 * (or a zeroed guard never opened) does nothing. */
typedef struct hostio_out {
    FILE *f;          /* the stream while open, else NULL */
    const char *path; /* as opened (NULL: standard output); kept for messages,
                         so it must outlive the guard's use */
    int why;          /* errno of the failed open or close; 0 when only the
                         stream's error flag told */
    int removable;    /* path itself names the regular file f writes */
} hostio_out;
int hostio_out_open(hostio_out *out, const char *path, const char *mode, char *err);
int hostio_out_close(hostio_out *out, char *err);
void hostio_out_abandon(hostio_out *out);

/* `name` labels messages (usually the file name; NULL for "PGM"). */
int hostio_pgm_parse(const uint8_t *buf, size_t len, const char *name, hostio_pgm_view *out,
                     char *err);
int hostio_pgm_read(const char *path, hostio_image *out, char *err);
int hostio_pgm_write(const char *path, const hostio_image *img, char *err);
int hostio_pgm_fwrite(FILE *stream, const char *name, const hostio_image *img, char *err);
void hostio_image_free(hostio_image *img);
struct actag_frame;
/* The image as the core library's frame (actag/actag.h): data, rows, cols,
 * stride and depth, the pixels not copied. */
void hostio_image_frame(const hostio_image *img, struct actag_frame *frame);
int hostio_ppm_write(const char *path, const uint8_t *rgb, int rows, int cols, char *err);

/* A PGM (by its P5 magic) or a raw frame (raw may be NULL: PGM only). The
 * image is malloc'd with stride = raw stride (or cols for PGM); a raw image
 * holds (rows - 1) x stride + cols samples (the last row's padding is not
 * kept, so a small file never costs a large allocation).
 *   - With a raw layout given (rows, cols > 0), a file whose size fits it
 *     (rows x stride samples, the last row's padding optional) is raw even
 *     when it starts with "P5"; other files are read as PGM.
 *   - Every PGM sample must be <= maxval (else an error naming the sample's
 *     row and column); 8-bit samples of a maxval below 255 are scaled to
 *     0..255 (v * 255 / maxval, rounded) and img.maxval is then 255; 16-bit
 *     samples are returned as stored (actag_detect scales a 16-bit frame by
 *     its maximum).
 *   - Raw sizes are computed without overflow on 32-bit hosts: a layout too
 *     large to address is an error.
 * hostio_frame_parse() does the same on a buffer already in memory (name
 * labels messages; NULL for "frame"). */
int hostio_frame_read(const char *path, const hostio_raw_spec *raw, hostio_image *out,
                      char *err);
int hostio_frame_parse(const uint8_t *buf, size_t len, const char *name,
                       const hostio_raw_spec *raw, hostio_image *out, char *err);
const char *hostio_frame_name(const char *path);

/* Number parsing: name is the option (e.g. "--max-range") shown in messages. */
int hostio_parse_double(const char *name, const char *s, double lo, double hi, double *v,
                        char *err);
int hostio_parse_long(const char *name, const char *s, long lo, long hi, long *v, char *err);
/* The same for a whole number lo..hi in 32 unsigned bits (a seed), where
 * long may be 32 bits wide (32-bit ARM Linux): no sign, no wrap. */
int hostio_parse_u32(const char *name, const char *s, uint32_t lo, uint32_t hi, uint32_t *v,
                     char *err);
/* Exactly n finite numbers separated by `sep` (e.g. ','). */
int hostio_parse_doubles(const char *name, const char *s, char sep, double *out, int n,
                         char *err);

int hostio_parse_list(const char *name, const char *s, double *out, int cap, int *n,
                      char *err);
/* One of n words (choices[0 .. n-1]): *index is its position. The message
 * of a miss names the option, the words and the value. */
int hostio_parse_choice(const char *name, const char *s, const char *const *choices, int n,
                        int *index, char *err);
/* A bearing table: exactly cols numbers (see MANUAL); cols_opt NULL: the
 * frame's columns. */
int hostio_parse_bearings(const char *name, const char *text, int cols, const char *cols_opt,
                          float *out, char *err);
int hostio_read_bearings(const char *path, int cols, const char *cols_opt, float *out,
                         char *err);

/* The folder's entries named PREFIX...SUFFIX as sorted "dir/name" paths
 * (host only). */
char **hostio_list_dir(const char *dir, const char *prefix, const char *suffix, int *n,
                       char *err);
void hostio_list_free(char **names, int n);

/* Family code list: *n codes stored (error when the file holds more than cap). */
int hostio_read_codes(const char *path, uint32_t *codes, size_t cap, size_t *n, char *err);

/* s as a JSON string literal (quotes included) on stream. */
void hostio_json_string(FILE *stream, const char *s);

/* A JSON number (fmt of v) in buf, or "null" when have is 0. */
#define HOSTIO_JNUM_LEN 48
const char *hostio_json_num(char *buf, const char *fmt, double v, int have);

/* Shell command line; exit status 0..255, or -1 when it did not run or exit. */
int hostio_run(const char *cmd, char *err);

/* A library field and the command-line option that sets it. */
typedef struct hostio_optname {
    const char *field;  /* as actag_error_detail names it: "tag_size", "geometry.max_range" */
    const char *option; /* "--tag-size" */
    double scale;       /* option units per library unit (0 means 1): 57.2957795 for a
                           radian field set in degrees */
} hostio_optname;

struct actag_error_detail;
/* The detail as a one-line message in err (HOSTIO_ERRLEN). Returns 0, or -1
 * for a NULL detail or err. */
int hostio_detail_message(const struct actag_error_detail *d, const hostio_optname *map,
                          int nmap, char *err);

/* For command-line tools: the message on stderr as "prog: msg", exit status 2. */
void hostio_die(const char *prog, const char *msg);
/* Results lost on standard output are an error, not exit 0: fflush and the
 * stream's error flag, else hostio_die(prog, "standard output: write error"). */
void hostio_stdout_check(const char *prog);
double hostio_opt_double(const char *prog, const char *name, const char *s, double lo,
                         double hi);
long hostio_opt_long(const char *prog, const char *name, const char *s, long lo, long hi);
uint32_t hostio_opt_u32(const char *prog, const char *name, const char *s, uint32_t lo,
                        uint32_t hi);
/* hostio_parse_choice's index, or dies with its message. */
int hostio_opt_choice(const char *prog, const char *name, const char *s,
                      const char *const *choices, int n);
/* The folder of option `name` and its parents (hostio_mkdirs), or dies with
 * "prog: name: <hostio_mkdirs' message>". */
void hostio_opt_mkdirs(const char *prog, const char *name, const char *path);
/* The value of option argv[*i], the next argument (*i moves onto it), or
 * dies with "prog: OPTION: missing value" when argv[*i] is the last. */
const char *hostio_opt_value(const char *prog, int argc, char **argv, int *i);
/* Dies with "prog: unknown option 'OPT' (try --help)". */
void hostio_opt_unknown(const char *prog, const char *opt);

#ifdef __cplusplus
}
#endif
#endif
