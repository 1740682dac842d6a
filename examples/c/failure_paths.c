/*
 * failure_paths.c: every way a host program can misuse libaddipos, each
 * answered with its error code and nothing crashing or hanging: NULL
 * pointers, unknown objects, wrong types, the null handle, handles made
 * stale by a Clean, handles of another connection, axes out of range, a
 * closed connection, huge cycle counts, a wait that runs into its
 * timeout, a server that is not there. Prints one line per check that
 * failed and "N passed, M failed"; exits 0 only when all passed.
 *
 *   ./failure_paths            the checks on an embedded emulator
 *   ./failure_paths 1300       the same on a running `addipos serve`
 *                              (started with --no-persist: it is changed)
 */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <stdint.h>

#include "addipos.h"

static int passed, failed;

static void expect(const char *what, uint32_t got, uint32_t want)
{
    if (got == want) {
        passed++;
    } else {
        failed++;
        printf("FAIL %s: got 0x%08x, want 0x%08x\n", what, (unsigned)got, (unsigned)want);
    }
}

static void truth(const char *what, int ok)
{
    expect(what, ok ? 0 : 1, 0);
}

static uoi_descriptor obj(int32_t bus, int32_t device, int32_t index, int32_t sub)
{
    uoi_descriptor d = {bus, device, index, sub};
    return d;
}

/* "Ask for the size first": size 0 gives the text's length, and a buffer
 * of that length + 1 holds it whole. */
static void error_copy_sizes(addipos *a)
{
    char buf[512];
    size_t len = strlen(addipos_error_text(a));
    truth("addipos_error_copy size 0 gives the length", addipos_error_copy(a, buf, 0) == len);
    truth("addipos_error_copy NULL gives the length", addipos_error_copy(a, NULL, 0) == len);
    truth("the length fits the buffer", len > 0 && len + 1 <= sizeof buf);
    if (len + 1 <= sizeof buf) {
        truth("addipos_error_copy copies it whole", addipos_error_copy(a, buf, len + 1) == len
                                                        && strcmp(buf, addipos_error_text(a)) == 0);
    }
}

static void null_pointers(addipos *a)
{
    uoi_descriptor plane = obj(1300, 0, 3, 0);
    uoi_handle h = 0;
    int32_t i;
    double p[8] = {0};
    expect("uoi_init on NULL connection", uoi_init(NULL, &plane, &h), ADDIPOS_E_ARGUMENT);
    expect("tc_lin on NULL connection", tc_lin(NULL, 1, p, 100), ADDIPOS_E_ARGUMENT);
    expect("tc_exec on NULL connection", tc_exec(NULL, 1), ADDIPOS_E_ARGUMENT);
    truth("error text of NULL is empty", strcmp(addipos_error_text(NULL), "") == 0);
    addipos_close(NULL);
    expect("uoi_init NULL descriptor", uoi_init(a, NULL, &h), ADDIPOS_E_ARGUMENT);
    expect("uoi_init NULL handle", uoi_init(a, &plane, NULL), ADDIPOS_E_ARGUMENT);
    truth("an argument error is explained", strstr(addipos_error_text(a), "NULL") != NULL);
    error_copy_sizes(a);
    expect("uoi_init", uoi_init(a, &plane, &h), ADDIPOS_OK);
    expect("uoi_read_int NULL value", uoi_read_int(a, h, NULL), ADDIPOS_E_ARGUMENT);
    expect("uoi_read_double NULL value", uoi_read_double(a, h, NULL), ADDIPOS_E_ARGUMENT);
    expect("tc_pos NULL", tc_pos(a, NULL), ADDIPOS_E_ARGUMENT);
    expect("tc_queue NULL", tc_queue(a, NULL), ADDIPOS_E_ARGUMENT);
    expect("tc_lin NULL pos with a mask", tc_lin(a, 1, NULL, 100), ADDIPOS_E_ARGUMENT);
    expect("tc_ja NULL pos with a mask", tc_ja(a, 2, NULL), ADDIPOS_E_ARGUMENT);
    expect("tc_cir NULL ijk with a mask", tc_cir(a, 1, 3, p, 1, NULL, 100), ADDIPOS_E_ARGUMENT);
    expect("uoi_clean_handle NULL", uoi_clean_handle(a, NULL), ADDIPOS_E_ARGUMENT);
    expect("addipos_record NULL path stops nothing", addipos_record(a, NULL), ADDIPOS_OK);
    expect("still readable", uoi_read_int(a, h, &i), ADDIPOS_OK);
}

static void unknown_objects_and_types(addipos *a)
{
    uoi_descriptor d;
    uoi_handle h = 77, plane, radius, clean, wear, wkz;
    int32_t i;
    double x;
    d = obj(1300, 0, 99, 0);
    expect("no object", uoi_init(a, &d, &h), ADDIPOS_E_NO_OBJECT);
    expect("refused handle is 0", h, 0);
    d = obj(1300, 1, 1, 99);
    expect("no subindex", uoi_init(a, &d, &h), ADDIPOS_E_NO_SUBINDEX);
    d = obj(1301, 0, 3, 0);
    expect("another bus", uoi_init(a, &d, &h), ADDIPOS_E_NO_OBJECT);
    d = obj(1300, 1, 33, 1);
    expect("group 33", uoi_init(a, &d, &h), ADDIPOS_E_NO_OBJECT);
    d = obj(1300, -1, 0, 0);
    expect("negative device", uoi_init(a, &d, &h), ADDIPOS_E_NO_OBJECT);
    d = obj(1300, 0, 3, 0);   expect("TcPlane", uoi_init(a, &d, &plane), ADDIPOS_OK);
    d = obj(1300, 1, 1, 6);   expect("RADIUS", uoi_init(a, &d, &radius), ADDIPOS_OK);
    d = obj(1300, 0, 1, 0);   expect("Clean", uoi_init(a, &d, &clean), ADDIPOS_OK);
    d = obj(1300, 3, 1, 10);  expect("WearRadius", uoi_init(a, &d, &wear), ADDIPOS_OK);
    d = obj(1300, 1, 1, 8);   expect("WKZINDEX", uoi_init(a, &d, &wkz), ADDIPOS_OK);
    expect("i32 read as double", uoi_read_double(a, plane, &x), ADDIPOS_E_TYPE_MISMATCH);
    expect("double written as i32", uoi_write_int(a, radius, 2), ADDIPOS_E_TYPE_MISMATCH);
    expect("write-only read", uoi_read_int(a, clean, &i), ADDIPOS_E_WRITE_ONLY);
    expect("read-only written", uoi_write_double(a, wear, 1.0), ADDIPOS_E_READ_ONLY);
    expect("out of range", uoi_write_int(a, wkz, 5000), ADDIPOS_E_RANGE);
    expect("non-finite", uoi_write_double(a, radius, INFINITY), ADDIPOS_E_RANGE);
    expect("null handle", uoi_read_int(a, 0, &i), ADDIPOS_E_NULL_HANDLE);
    expect("made-up handle", uoi_read_int(a, 0x12345678u, &i), ADDIPOS_E_BAD_HANDLE);
    expect("plane reads 17", uoi_read_int(a, plane, &i), ADDIPOS_OK);
    expect("17", (uint32_t)i, 17);
}

static void clean_makes_handles_stale(addipos *a)
{
    uoi_descriptor d = obj(1300, 0, 3, 0), c = obj(1300, 0, 1, 0);
    uoi_handle plane, clean;
    int32_t i;
    expect("init plane", uoi_init(a, &d, &plane), ADDIPOS_OK);
    expect("init clean", uoi_init(a, &c, &clean), ADDIPOS_OK);
    expect("Clean = 2 is refused", uoi_write_int(a, clean, 2), ADDIPOS_E_RANGE);
    expect("a refused Clean voids nothing", uoi_read_int(a, plane, &i), ADDIPOS_OK);
    expect("Clean", uoi_write_int(a, clean, 1), ADDIPOS_OK);
    expect("stale after Clean", uoi_read_int(a, plane, &i), ADDIPOS_E_STALE_HANDLE);
    const char *why = addipos_error_text(a);
    truth("the text says why", strstr(why, "Clean") != NULL);
    truth("the text says what to do", strstr(why, "uoi_init") != NULL);
    expect("the Clean handle too", uoi_write_int(a, clean, 1), ADDIPOS_E_STALE_HANDLE);
    expect("init again", uoi_init(a, &d, &plane), ADDIPOS_OK);
    expect("works again", uoi_read_int(a, plane, &i), ADDIPOS_OK);
    uoi_handle old = plane;
    expect("release", uoi_clean_handle(a, &plane), ADDIPOS_OK);
    expect("released handle nulled", plane, 0);
    expect("released handle is stale", uoi_read_int(a, old, &i), ADDIPOS_E_STALE_HANDLE);
    expect("releasing 0 is allowed", uoi_clean_handle(a, &plane), ADDIPOS_OK);
}

static void axes_out_of_range(addipos *a)
{
    double p[8] = {1, 2, 3, 4, 5, 6, 7, 8}, ijk[3] = {1, 0, 0};
    expect("tc_ssf axis 8", tc_ssf(a, 8, 2001), ADDIPOS_E_ARGUMENT);
    expect("tc_ssf axis huge", tc_ssf(a, 0xFFFFFFFFu, 2001), ADDIPOS_E_ARGUMENT);
    expect("tc_lin mask bit 8", tc_lin(a, 0x100, p, 100), ADDIPOS_E_ARGUMENT);
    expect("tc_rap mask bit 31", tc_rap(a, 0x80000000u, p), ADDIPOS_E_ARGUMENT);
    expect("tc_ja mask bit 9", tc_ja(a, 0x201, p), ADDIPOS_E_ARGUMENT);
    expect("tc_js mask bit 8", tc_js(a, 0x1FF), ADDIPOS_E_ARGUMENT);
    expect("tc_cir ijk bit 3", tc_cir(a, 0, 3, p, 8, ijk, 100), ADDIPOS_E_ARGUMENT);
    expect("coordinate beyond 1e9", (p[0] = 2e9, tc_lin(a, 1, p, 100)), ADDIPOS_E_RANGE);
    expect("a negative feed", (p[0] = 1, tc_lin(a, 1, p, -5)), ADDIPOS_E_RANGE);
    truth("the feed error names the feed", strstr(addipos_error_text(a), "feed") != NULL);
    expect("tc_ssf axis 7", tc_ssf(a, 7, 2001), ADDIPOS_OK);
    expect("tc_js all axes", tc_js(a, 0xFF), ADDIPOS_OK);
    expect("huge EXEC on an empty spooler", tc_exec(a, 0xFFFFFFFFFFFFFFFEull), ADDIPOS_OK);
    expect("EXEC_ALL", tc_exec(a, ADDIPOS_EXEC_ALL), ADDIPOS_OK);
}

static void connections(addipos *a)
{
    addipos *b = addipos_open("embedded");
    truth("second connection", b != NULL);
    uoi_descriptor d = obj(1300, 0, 3, 0);
    uoi_handle hb;
    int32_t i;
    expect("init on b", uoi_init(b, &d, &hb), ADDIPOS_OK);
    expect("b's handle on a", uoi_read_int(a, hb, &i), ADDIPOS_E_BAD_HANDLE);
    addipos_close(b);
    expect("closed connection", uoi_read_int(b, hb, &i), ADDIPOS_E_CONNECTION);
    expect("closed connection exec", tc_exec(b, 1), ADDIPOS_E_CONNECTION);
    truth("closed connection has a text", strlen(addipos_error_text(b)) > 0);
    addipos_close(b);
    truth("bad target", addipos_open("plc:") == NULL);
    truth("bad target explained", strlen(addipos_open_error()) > 0);
    truth("bad factor", addipos_open("embedded:realtime=0") == NULL);
    /* Nobody listens on port 1: refused at open, said why. */
    truth("no server there", addipos_open("127.0.0.1:1") == NULL);
    truth("no server explained", strstr(addipos_open_error(), "127.0.0.1:1") != NULL);

    /* A real-time wait runs into its timeout instead of blocking. */
    addipos *rt = addipos_open("embedded:realtime=1");
    truth("real-time connection", rt != NULL);
    expect("timeout 50 ms", addipos_set_timeout(rt, 50), ADDIPOS_OK);
    expect("waiting for ever", tc_exec(rt, 0xFFFFFFFFFFFFFFFEull), ADDIPOS_E_TIMEOUT);
    double p[8] = {1000};
    expect("a long line", tc_lin(rt, 1, p, 60), ADDIPOS_OK);
    expect("waiting for it", tc_exec(rt, ADDIPOS_EXEC_ALL), ADDIPOS_E_TIMEOUT);
    uint32_t n;
    expect("queue", tc_queue(rt, &n), ADDIPOS_OK);
    expect("still moving", n, 1);
    addipos_close(rt);
}

int main(int argc, char **argv)
{
    truth("version", strlen(addipos_version()) > 0);
    /* The connection under test: embedded, or the target given (a server). */
    addipos *a = addipos_open(argc > 1 ? argv[1] : "embedded");
    if (a == NULL) {
        printf("addipos_open: %s\n", addipos_open_error());
        return 1;
    }
    null_pointers(a);
    unknown_objects_and_types(a);
    clean_makes_handles_stale(a);
    axes_out_of_range(a);
    connections(a);
    addipos_close(a);
    printf("%d passed, %d failed\n", passed, failed);
    return failed == 0 ? 0 : 1;
}
