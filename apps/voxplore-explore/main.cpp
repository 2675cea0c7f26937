// voxplore-explore: autonomous exploration of a simulated building (see --help).
#include <voxplore/apps/ExploreApp.h>

int main(int argc, char** argv) { return voxplore::apps::ExploreApp{}.run(argc, argv); }
