/*
 * test_param.c — the parameter table is well formed and its checks name the
 * field at fault (param.h contract).
 */
#include "test_util.h"

#include <string.h>

#include "sim/config.h"

static void table_rows_are_well_formed(void **state)
{
    (void)state;
    int n = ts_param_nsections();
    assert_true(n >= 9);
    for (int s = 0; s < n; s++) {
        const ts_param_section *sec = ts_param_section_at(s);
        assert_non_null(sec);
        assert_true(sec->nparams > 0);
        char prefix[64];
        snprintf(prefix, sizeof prefix, "/%s/", sec->name);
        for (int i = 0; i < sec->nparams; i++) {
            const ts_param *p = &sec->params[i];
            if (strncmp(p->pointer, prefix, strlen(prefix)) != 0)
                fail_msg("%s is not under section %s", p->pointer, sec->name);
            assert_non_null(p->unit);
            assert_non_null(p->description);
            assert_true(strlen(p->description) > 5);
            assert_true(p->offset + sizeof(int) <= sizeof(ts_config));
            if (p->type == TS_PT_DOUBLE || p->type == TS_PT_INT || p->type == TS_PT_DARRAY)
                assert_true(p->min <= p->max);
            if (p->type == TS_PT_ENUM) {
                assert_non_null(p->enum_names);
                assert_non_null(p->enum_names[0]);
            }
            if (p->type == TS_PT_DARRAY || p->type == TS_PT_STRING) assert_true(p->capacity > 0);
            assert_ptr_equal(ts_param_find(p->pointer), p); /* pointers are unique */
        }
    }
    assert_null(ts_param_find("/track/no_such_field"));
}

static void range_check_names_the_field(void **state)
{
    (void)state;
    const ts_param *p = ts_param_find("/track/n_trans");
    assert_non_null(p);
    ts_err err;
    ts_err_clear(&err);
    assert_int_equal(ts_param_check_number(p, 12, &err), TS_OK);
    assert_int_equal(ts_param_check_number(p, 99, &err), TS_ERR_RANGE);
    assert_string_equal(err.pointer, "/track/n_trans");
    assert_non_null(strstr(err.msg, "got 99"));
    assert_int_equal(ts_param_check_number(p, NAN, &err), TS_ERR_RANGE);
}

static void validate_catches_bad_struct_values(void **state)
{
    (void)state;
    ts_config c;
    memset(&c, 0, sizeof c);
    ts_err err;
    /* An all-zero config violates at least the first positive-minimum field. */
    assert_int_not_equal(ts_param_validate(&c, &err), TS_OK);
    assert_true(err.pointer[0] == '/');
}

static void enum_lookup(void **state)
{
    (void)state;
    const ts_param *p = ts_param_find("/track/fidelity");
    assert_int_equal(ts_param_enum_index(p, "coupled"), TS_TRACK_COUPLED);
    assert_int_equal(ts_param_enum_index(p, "static"), TS_TRACK_STATIC);
    assert_int_equal(ts_param_enum_index(p, "bogus"), -1);
    assert_string_equal(ts_rc_name(TS_ERR_RANGE), "TS_ERR_RANGE");
    assert_string_equal(ts_rc_name((ts_rc)999), "TS_ERR_UNKNOWN");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(table_rows_are_well_formed),
        cmocka_unit_test(range_check_names_the_field),
        cmocka_unit_test(validate_catches_bad_struct_values),
        cmocka_unit_test(enum_lookup),
    };
    return cmocka_run_group_tests_name("sim/param", tests, NULL, NULL);
}
