/*
 * test_param.c — the parameter table is well formed and its checks name the
 * field at fault (param.h contract).
 */
#include "test_util.h"

#include <string.h>

#include "preset_config.h"
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

/* EVIDENCE: param.h ts_param_validate ("ranges, enum indices, array
 * counts"), row by row over the whole table from a shipped preset's valid
 * config: every enum one past its last name, every boolean at 2 and every
 * array one element over its capacity is refused naming that field, the
 * last enum name and both booleans pass, and a non-finite array element is
 * refused naming the element (/pointer/0). */
static void validate_checks_every_enum_bool_and_array(void **state)
{
    (void)state;
    const ts_config base = test_preset_config("bump-prescribed-coupled", NULL);
    ts_err err;
    assert_int_equal(ts_param_validate(&base, &err), TS_OK);
    int seen[3] = {0, 0, 0};
    for (int sidx = 0; sidx < ts_param_nsections(); sidx++) {
        const ts_param_section *sec = ts_param_section_at(sidx);
        for (int i = 0; i < sec->nparams; i++) {
            const ts_param *p = &sec->params[i];
            ts_config c = base;
            char want[TS_ERR_POINTER_LEN + 8];
            snprintf(want, sizeof want, "%s", p->pointer);
            if (p->type == TS_PT_ENUM) {
                int count = 0;
                while (p->enum_names[count])
                    count++;
                ts_param_set_int(&c, p->offset, count - 1);
                assert_int_equal(ts_param_validate(&c, &err), TS_OK);
                ts_param_set_int(&c, p->offset, count);
                seen[0]++;
            } else if (p->type == TS_PT_BOOL) {
                for (int v = 0; v <= 1; v++) {
                    ts_param_set_int(&c, p->offset, v);
                    assert_int_equal(ts_param_validate(&c, &err), TS_OK);
                }
                ts_param_set_int(&c, p->offset, 2);
                seen[1]++;
            } else if (p->type == TS_PT_DARRAY) {
                ts_param_set_int(&c, p->count_offset, p->capacity + 1);
                assert_int_equal(ts_param_validate(&c, &err), TS_ERR_RANGE);
                assert_string_equal(err.pointer, p->pointer);
                c = base;
                ts_param_set_int(&c, p->count_offset, 1);
                ts_param_set_double(&c, p, 0, NAN);
                snprintf(want, sizeof want, "%s/0", p->pointer);
                seen[2]++;
            } else {
                continue;
            }
            assert_int_equal(ts_param_validate(&c, &err), TS_ERR_RANGE);
            if (strcmp(err.pointer, want) != 0) fail_msg("%s: error names '%s'", want, err.pointer);
        }
    }
    print_message("      %d enums, %d booleans, %d arrays\n", seen[0], seen[1], seen[2]);
    assert_true(seen[0] > 5 && seen[1] > 2 && seen[2] > 2);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(table_rows_are_well_formed),
        cmocka_unit_test(range_check_names_the_field),
        cmocka_unit_test(validate_catches_bad_struct_values),
        cmocka_unit_test(enum_lookup),
        cmocka_unit_test(validate_checks_every_enum_bool_and_array),
    };
    return cmocka_run_group_tests_name("sim/param", tests, NULL, NULL);
}
