// A panel plugin for the TestDependent module that lacks the factory: the loader names it.
extern "C" __attribute__((visibility("default"))) int roboplan_not_a_panel() { return 0; }
