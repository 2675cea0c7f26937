// voxplore-replay: offline SlamIcp over a rawlog (see --help).
#include <voxplore/apps/ReplayApp.h>

int main(int argc, char** argv) { return voxplore::apps::ReplayApp{}.run(argc, argv); }
