// voxplore-plan: one planning step of a run planned again from its saved inputs (see --help).
#include <voxplore/apps/PlanApp.h>

int main(int argc, char** argv) { return voxplore::apps::PlanApp{}.run(argc, argv); }
