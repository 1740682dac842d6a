/*
 * using_tc.c: the TC manual's "Using TC" sequence as a legacy PCAP host
 * program does it, through libaddipos (docs/host-api.md, "The example").
 *
 *   make -C examples/c run                       (stepped embedded emulator)
 *   make -C examples/c run TARGET=embedded:realtime=10
 *
 * Group 1 corrects tool 3 (radius 2) on the left of a 20 x 20 square
 * driven counter-clockwise from (0,0), then leaves it to (-5,-5). The
 * corrected path, worked out by hand: the approach to (18,2), the inside
 * corners (18,18) and (2,18), the held last side to (2,0) when STATUS
 * goes to 0, the departure to (-5,-5).
 */
#include <stdio.h>
#include <stdint.h>

#include "addipos.h"

/* Every call returns ADDIPOS_OK or an error code; stop on the first. */
#define CHECK(call)                                                        \
    do {                                                                   \
        uint32_t rc_ = (call);                                             \
        if (rc_ != ADDIPOS_OK) {                                           \
            fprintf(stderr, "%s: 0x%08x: %s\n", #call, (unsigned)rc_,      \
                    addipos_error_text(a));                                \
            addipos_close(a);                                              \
            return 1;                                                      \
        }                                                                  \
    } while (0)

/* An object of the TC module (bus 1300). */
static uoi_descriptor tc(int32_t device, int32_t index, int32_t sub)
{
    uoi_descriptor d = {1300, device, index, sub};
    return d;
}

/* Bits of the axis mask: X and Y. */
#define XY 3u

int main(int argc, char **argv)
{
    /* NULL: $ADDIPOS_TARGET, else an embedded emulator, stepped. */
    addipos *a = addipos_open(argc > 1 ? argv[1] : NULL);
    if (a == NULL) {
        fprintf(stderr, "addipos_open: %s\n", addipos_open_error());
        return 1;
    }

    /* Initialise the object descriptors of group 1 and get handles. */
    uoi_handle reset, xaxis, yaxis, zaxis, wkzindex, radius, left, status, error;
    uoi_descriptor d;
    d = tc(1, 1, 2);  CHECK(uoi_init(a, &d, &reset));
    d = tc(1, 1, 4);  CHECK(uoi_init(a, &d, &xaxis));
    d = tc(1, 1, 5);  CHECK(uoi_init(a, &d, &yaxis));
    d = tc(1, 1, 11); CHECK(uoi_init(a, &d, &zaxis));
    d = tc(1, 1, 8);  CHECK(uoi_init(a, &d, &wkzindex));
    d = tc(1, 1, 6);  CHECK(uoi_init(a, &d, &radius));
    d = tc(1, 1, 9);  CHECK(uoi_init(a, &d, &left));
    d = tc(1, 1, 3);  CHECK(uoi_init(a, &d, &status));
    d = tc(1, 1, 1);  CHECK(uoi_init(a, &d, &error));

    /* Initialisation of the tool radius correction. */
    CHECK(tc_rs(a));                          /* rs(): no coordinate rotation */
    CHECK(uoi_write_int(a, reset, 0));        /* RESET the group */
    CHECK(uoi_write_int(a, xaxis, 0));        /* the plane: X on axis 0, */
    CHECK(uoi_write_int(a, yaxis, 1));        /* Y on axis 1, */
    CHECK(uoi_write_int(a, zaxis, 2));        /* the tool length on axis 2 */
    CHECK(uoi_write_int(a, wkzindex, 3));     /* tool index 3 of the table, */
    CHECK(uoi_write_double(a, radius, 2.0));  /* its radius */

    /* Using it: tool, side, STATUS = 1, spool, STATUS = 0. */
    CHECK(uoi_write_int(a, wkzindex, 3));
    CHECK(uoi_write_int(a, left, 0));         /* correct on the left */
    CHECK(uoi_write_int(a, status, 1));       /* STATUS = 1: Run */
    double p[8] = {0};
    p[0] = 20; p[1] = 0;  CHECK(tc_lin(a, XY, p, 600.0));  /* held */
    p[0] = 20; p[1] = 20; CHECK(tc_lin(a, XY, p, 0.0));    /* spools the approach */
    p[0] = 0;  p[1] = 20; CHECK(tc_lin(a, XY, p, 0.0));
    p[0] = 0;  p[1] = 0;  CHECK(tc_lin(a, XY, p, 0.0));
    CHECK(uoi_write_int(a, status, 0));       /* STATUS = 0: the held side is spooled */
    p[0] = -5; p[1] = -5; CHECK(tc_rap(a, XY, p));          /* the departure */

    /* Wait until the queue is empty: stepped, tc_exec runs 100 cycles;
       in real time it waits for them. */
    uint32_t waiting;
    for (;;) {
        CHECK(tc_queue(a, &waiting));
        if (waiting == 0)
            break;
        CHECK(tc_exec(a, 100));
    }

    double pos[8];
    int32_t err;
    CHECK(tc_pos(a, pos));
    CHECK(uoi_read_int(a, error, &err));
    printf("position X%g Y%g Z%g\n", pos[0], pos[1], pos[2]);
    printf("ERROR %d\n", (int)err);
    addipos_close(a);
    return err == 0 ? 0 : 2;
}
