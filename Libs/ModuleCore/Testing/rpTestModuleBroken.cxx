// A shared object that looks like a module by name but exports no entry point.
extern "C" int roboplan_not_a_module() { return 1; }
