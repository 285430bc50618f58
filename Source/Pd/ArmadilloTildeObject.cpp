// Pure Data's [armadillo~] (issue 46): the instrument's control step clocked by Pd's DSP blocks
// (live::BlockInstrument through Pd/BlockHost.h), as a plugin host's blocks clock the plugin's;
// the scene's sound out of the first (signal) outlet, the messages out of the second, presented
// on a Pd clock (Pd/PdFront.h). Loaded by Pd from armadillo~.pd_linux (armadillo_tilde_setup).
#include "Pd/BlockHost.h"
#include "Pd/PdFront.h"

namespace armadillo::pd {
namespace {

// ---- [armadillo~] -------------------------------------------------------------------------------

t_class* tildeClass = nullptr;

struct ArmadilloTilde {
    t_object obj;
    BlockHost* host;
    Front* front;
};

void tildeTick(ArmadilloTilde* x) { x->front->present(); }

void* tildeNew(t_symbol*, int, t_atom*)
{
    auto* x = reinterpret_cast<ArmadilloTilde*>(pd_new(tildeClass));
    try {
        x->host = new BlockHost(sys_getsr() > 0 ? static_cast<double>(sys_getsr()) : 48000.0);
        x->front = new Front(*x->host, canvas_getdir(canvas_getcurrent())->s_name);
    } catch (const std::exception& e) {
        pd_error(x, "armadillo~: %s", e.what());
        return nullptr;
    }
    x->host->setCommands(&x->front->commands);
    outlet_new(&x->obj, &s_signal);                        // the scene's sound, mono
    x->front->out = outlet_new(&x->obj, &s_anything);      // the messages
    x->front->clock = clock_new(x, method(tildeTick));
    x->front->lastStatus = clock_getlogicaltime();
    try {
        x->host->apply(x->front->commands.settings());     // the engine of the default scene
    } catch (const std::exception& e) {
        pd_error(x, "armadillo~: %s", said(e).c_str());
    }
    clock_delay(x->front->clock, kPollMs);
    return x;
}

void tildeFree(ArmadilloTilde* x)
{
    if (x->front && x->front->clock) clock_free(x->front->clock);
    delete x->front;
    delete x->host;
}

/// The DSP method: one Pd block is one host block of the instrument's block clock. Real-time:
/// BlockHost::render allocates, locks and waits for nothing (Tests/Pd/BlockHostRealtimeTests.cpp).
t_int* tildePerform(t_int* w)
{
    auto* host = reinterpret_cast<BlockHost*>(w[1]);
    auto* out = reinterpret_cast<t_sample*>(w[2]);
    const int n = static_cast<int>(w[3]);
    host->render(out, n);
    return w + 4;
}

void tildeDsp(ArmadilloTilde* x, t_signal** sp)
{
    // Not real-time (Pd's thread, DSP being rebuilt): the block size and rate are taken here.
    x->host->prepare(sp[0]->s_sr, sp[0]->s_n);
    dsp_add(tildePerform, 3, x->host, sp[0]->s_vec, static_cast<t_int>(sp[0]->s_n));
}

void tildeAnything(ArmadilloTilde* x, t_symbol* s, int argc, t_atom* argv) { x->front->message(x, "armadillo~", s, argc, argv); }
void tildeBang(ArmadilloTilde* x) { x->front->message(x, "armadillo~", gensym("bang"), 0, nullptr); }

} // namespace

void registerArmadilloTilde()
{
    if (zgetfn(&pd_objectmaker, gensym("armadillo~")) != nullptr) return;   // registered already: the library loaded under its other name
    tildeClass = class_new(gensym("armadillo~"), newMethod(tildeNew),
                           method(tildeFree), sizeof(ArmadilloTilde), CLASS_DEFAULT, A_GIMME, 0);
    class_addbang(tildeClass, method(tildeBang));
    class_addanything(tildeClass, method(tildeAnything));
    class_addmethod(tildeClass, method(tildeDsp), gensym("dsp"), A_CANT, 0);
}

} // namespace armadillo::pd

/// Pd loads armadillo~.pd_linux (the same library under the class's name) for [armadillo~].
extern "C" __attribute__((visibility("default"))) void armadillo_tilde_setup(void)
{
    armadillo::pd::registerArmadillo();
    armadillo::pd::registerArmadilloTilde();
}
