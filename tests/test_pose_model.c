/* The sonar pose's least-squares model (src/pose_model.h): its analytic
 * Jacobian against central differences of its residuals, over the same
 * step the solver takes, at random poses with every prior in use. */
#include "../src/pose_model.h"
#include "../src/rotation.h"

#include "unity.h"
#include "test_util.h"

#include <math.h>

void setUp(void) {}
void tearDown(void) {}

/* A random model whose corners are those of a tag at a random pose (x),
 * measured with a little noise, with an elevation prior and a plane. */
static void random_case(actag__pose_model *m, actag__pose_state *x)
{
    float w[3], R[9], t[3], n[3], e[3] = {0.0f, 0.0f, 0.0f}, len;
    double r = tu_uniform(0.5, 4.0), a = tu_uniform(-0.5, 0.5), el = tu_uniform(0.05, 0.15) * (tu_rand() & 1u ? 1 : -1);
    static const float cx[4] = {-0.5f, 0.5f, 0.5f, -0.5f}, cy[4] = {-0.5f, -0.5f, 0.5f, 0.5f};
    int i, j;
    memset(m, 0, sizeof *m);
    for (i = 0; i < 3; i++)
        w[i] = (float)tu_uniform(-0.7, 0.7);
    actag__rot_exp(w, R);
    t[0] = (float)(r * cos(el) * cos(a));
    t[1] = (float)(r * cos(el) * sin(a));
    t[2] = (float)(r * sin(el));
    m->s = 0.13f;
    m->E = 8.0f / 3.0f;
    m->half_v = 0.1047f;
    m->sr = 0.005f;
    m->sa = 0.003f;
    m->mu = 0.02f;
    m->sp = 0.05f;
    for (i = 0; i < 4; i++) {
        float c[3] = {cx[i] * m->s, cy[i] * m->s, 0.0f}, q[3], p[3];
        actag__mat_vec(R, c, q);
        for (j = 0; j < 3; j++)
            p[j] = q[j] + t[j];
        m->r[i] = actag__norm3(p) + (float)tu_uniform(-0.004, 0.004);
        m->az[i] = (float)atan2(p[1], p[0]) + (float)tu_uniform(-0.003, 0.003);
    }
    /* a plane near the tag's centre, tilted a little from its face */
    for (i = 0; i < 3; i++)
        n[i] = R[3 * i + 2] + (float)tu_uniform(-0.1, 0.1);
    len = actag__norm3(n);
    for (i = 0; i < 3; i++)
        m->n[i] = n[i] / len;
    m->d = actag__dot3(m->n, t) + (float)tu_uniform(-0.02, 0.02);
    e[fabsf(m->n[0]) < 0.5f ? 0 : 1] = 1.0f;
    actag__cross3(m->n, e, m->u);
    len = actag__norm3(m->u);
    for (i = 0; i < 3; i++)
        m->u[i] /= len;
    actag__cross3(m->n, m->u, m->v);
    m->wd = 1.0f / 0.02f;
    m->wt = 1.0f / 0.1f;
    /* the state: the pose moved a little */
    for (i = 0; i < 3; i++) {
        x->t[i] = t[i] + (float)tu_uniform(-0.02, 0.02);
        w[i] = (float)tu_uniform(-0.05, 0.05);
    }
    actag__rot_exp(w, x->R);
    {
        float M[9];
        actag__mat_mul(x->R, R, M);
        memcpy(x->R, M, sizeof M);
    }
}

static void test_jacobian_against_central_differences(void)
{
    int t, k, i, compared = 0;
    tu_seed(91);
    for (t = 0; t < TU_TRIALS(400, 10); t++) {
        actag__pose_model m;
        actag__pose_state x, xp, xm;
        float f[ACTAG__POSE_NRES], fp[ACTAG__POSE_NRES], fm[ACTAG__POSE_NRES];
        float J[ACTAG__POSE_NRES * ACTAG__POSE_NPAR];
        float cost, sum = 0.0f;
        random_case(&m, &x);
        cost = actag__pose_eval(&m, &x, f, J);
        for (i = 0; i < ACTAG__POSE_NRES; i++)
            sum += f[i] * f[i];
        TEST_ASSERT_TRUE(cost == sum);
        for (k = 0; k < ACTAG__POSE_NPAR; k++) {
            float d[ACTAG__POSE_NPAR] = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f};
            const float h = 1e-3f;
            d[k] = h;
            actag__pose_step(&x, d, &xp);
            d[k] = -h;
            actag__pose_step(&x, d, &xm);
            actag__pose_eval(&m, &xp, fp, NULL);
            actag__pose_eval(&m, &xm, fm, NULL);
            for (i = 0; i < ACTAG__POSE_NRES; i++) {
                double fd = ((double)fp[i] - (double)fm[i]) / (2.0 * h);
                double an = J[i * ACTAG__POSE_NPAR + k];
                char msg[120];
                snprintf(msg, sizeof msg, "residual %d over parameter %d: analytic %.6g, differences %.6g",
                         i, k, an, fd);
                /* float residuals of a few sds differenced over 2e-3: 0.1 of noise */
                TEST_ASSERT_TRUE_MESSAGE(fabs(an - fd) <= 0.1 + 0.01 * fabs(an), msg);
                compared += fabs(an) > 1.0;
            }
        }
    }
    /* the rows were not all zero */
    TEST_ASSERT_TRUE(compared > TU_TRIALS(400, 10) * 30);
}

/* A step of zero leaves the state as it is, and a step's rotation is a
 * rotation: R R^T = I after any step. */
static void test_the_step(void)
{
    int t, i, j, l;
    tu_seed(92);
    for (t = 0; t < TU_TRIALS(2000, 10); t++) {
        actag__pose_model m;
        actag__pose_state x, o;
        float d[ACTAG__POSE_NPAR] = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f};
        random_case(&m, &x);
        actag__pose_step(&x, d, &o);
        for (i = 0; i < 3; i++)
            TEST_ASSERT_TRUE(o.t[i] == x.t[i]);
        for (i = 0; i < 9; i++)
            TEST_ASSERT_FLOAT_WITHIN(2e-6f, x.R[i], o.R[i]);
        for (i = 0; i < ACTAG__POSE_NPAR; i++)
            d[i] = (float)tu_uniform(-1.0, 1.0);
        actag__pose_step(&x, d, &o);
        for (i = 0; i < 3; i++)
            TEST_ASSERT_TRUE(o.t[i] == x.t[i] + d[i]);
        for (i = 0; i < 3; i++)
            for (j = 0; j < 3; j++) {
                float s = 0.0f;
                for (l = 0; l < 3; l++)
                    s += o.R[3 * i + l] * o.R[3 * j + l];
                TEST_ASSERT_FLOAT_WITHIN(2e-6f, i == j ? 1.0f : 0.0f, s);
            }
    }
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_jacobian_against_central_differences);
    RUN_TEST(test_the_step);
    return UNITY_END();
}
