/* The user's part of tests/codegen/models/declared.rct: one C function per instantiation of the
   generic Weight(s: Set(?X * nat), x: ?X): nat, as robogen names them. With ?X = int: the sum of
   the positions paired with x; with ?X = boolean: how many pairs hold x. */
static uint64_t rg_user_Weight__int(rg_set_tup2_i_u s, int64_t x)
{
    uint64_t k, sum = 0;
    for (k = 0; k < s.n; k++)
        if (s.a[k]._1 == x) sum += s.a[k]._2;
    return sum;
}

static uint64_t rg_user_Weight__boolean(rg_set_tup2_b_u s, bool x)
{
    uint64_t k, count = 0;
    for (k = 0; k < s.n; k++)
        if (s.a[k]._1 == x) count++;
    return count;
}
