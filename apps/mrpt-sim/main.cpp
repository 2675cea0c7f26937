// mrpt-sim: scripted scan tours in a simulated world (see --help).
#include <voxplore/apps/SimApp.h>

int main(int argc, char** argv) { return voxplore::apps::SimApp{}.run(argc, argv); }
