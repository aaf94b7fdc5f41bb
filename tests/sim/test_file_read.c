/*
 * test_file_read.c — the bounded whole-file reader shared by the terrain files
 * and the CLI's config files (sim/file_read.h).
 *
 * EVIDENCE: its contract. A file of exactly the bound is read and one byte
 * more is TS_ERR_LIMIT (the first config reader refused a file of exactly
 * 16 MiB, review of session 24); the bytes come back whole and NUL-terminated,
 * embedded NULs counted; TS_READ_REGULAR refuses a FIFO and a directory, which
 * TS_READ_ANY reads (the config file from `<(...)`); a missing file is
 * TS_ERR_NOTFOUND naming the path.
 */
#include "test_util.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "sim/file_read.h"

static void write_bytes(const char *path, size_t n)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    for (size_t i = 0; i < n; i++)
        fputc(i % 7 == 3 ? '\0' : 'a' + (int)(i % 26), f);
    fclose(f);
}

static void bound_and_contents(void **state)
{
    (void)state;
    char path[] = "/tmp/tanksim_file_readXXXXXX";
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    close(fd);
    static const size_t sizes[] = {0, 1, 4095, 4096, 10000};
    for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++) {
        size_t n = sizes[k], len = 99;
        write_bytes(path, n);
        ts_err err;
        for (size_t max = n; max <= n + 1; max++) { /* exactly the bound, and one over */
            char *b = ts_file_read(path, max, TS_READ_REGULAR, &len, &err);
            if (!b) fail_msg("%zu bytes, max %zu: %s", n, max, err.msg);
            assert_int_equal(len, n);
            assert_int_equal(b[n], '\0');
            for (size_t i = 0; i < n; i++)
                assert_int_equal(b[i], i % 7 == 3 ? '\0' : 'a' + (int)(i % 26));
            free(b);
        }
        if (n > 0) {
            assert_null(ts_file_read(path, n - 1, TS_READ_ANY, &len, &err));
            assert_int_equal(err.code, TS_ERR_LIMIT);
        }
    }
    unlink(path);
}

static void kinds_and_missing(void **state)
{
    (void)state;
    ts_err err;
    assert_null(ts_file_read("/tmp", 1 << 20, TS_READ_REGULAR, NULL, &err));
    assert_int_equal(err.code, TS_ERR_PARAM);
    assert_non_null(strstr(err.msg, "not a regular file"));
    char fifo[] = "/tmp/tanksim_fifoXXXXXX";
    int fd = mkstemp(fifo);
    assert_true(fd >= 0);
    close(fd);
    unlink(fifo);
    assert_int_equal(mkfifo(fifo, 0600), 0);
    pid_t pid = fork();
    if (pid == 0) { /* the writer: one short document, then the end */
        FILE *w = fopen(fifo, "w");
        if (w) fputs("{\"a\": 1}", w), fclose(w);
        _exit(0);
    }
    size_t len = 0;
    char *b = ts_file_read(fifo, 1 << 20, TS_READ_ANY, &len, &err);
    if (!b) fail_msg("%s", err.msg);
    assert_string_equal(b, "{\"a\": 1}");
    free(b);
    waitpid(pid, NULL, 0);
    unlink(fifo);
    assert_null(ts_file_read("/nonexistent/tanksim.json", 1 << 20, TS_READ_ANY, NULL, &err));
    assert_int_equal(err.code, TS_ERR_NOTFOUND);
    assert_non_null(strstr(err.msg, "'/nonexistent/tanksim.json'"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(bound_and_contents),
        cmocka_unit_test(kinds_and_missing),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
