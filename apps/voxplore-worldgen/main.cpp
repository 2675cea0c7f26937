// voxplore-worldgen: procedural office buildings for tests and campaigns (see --help).
#include <voxplore/apps/WorldGenApp.h>

int main(int argc, char** argv) { return voxplore::apps::WorldGenApp{}.run(argc, argv); }
