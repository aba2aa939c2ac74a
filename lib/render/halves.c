/* halves.c: rows of a picture on two threads (see halves.h). */
#include "halves.h"

#include <pthread.h>

typedef struct Half {
    RowsFn fn;
    void *ctx;
    int y0, y1;
} Half;

static void *run_half(void *arg)
{
    Half *h = arg;
    h->fn(h->ctx, h->y0, h->y1, 1);
    return NULL;
}

void rows_in_halves(int h, int min_rows, RowsFn fn, void *ctx)
{
    if (h < 1) return;
    int mid = h / 2;
    Half second = {fn, ctx, mid, h};
    pthread_t t;
    if (h < min_rows || h < 2 || pthread_create(&t, NULL, run_half, &second) != 0) {
        fn(ctx, 0, h, 0);
        return;
    }
    fn(ctx, 0, mid, 0);
    pthread_join(t, NULL);
}
