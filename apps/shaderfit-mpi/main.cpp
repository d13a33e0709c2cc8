// shaderfit-mpi: the shaderfit command line with searches across MPI ranks
// (docs/distributed.md): `mpirun -np 4 shaderfit-mpi search ...`. Every rank runs the same
// command on the same data; rank 0 prints and writes files, the others evolve their islands.
// A separate program so that shaderfit itself neither links MPI nor pays for starting it.
#include <mpi.h>

#include <chrono>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <thread>

#include "cli.hpp"  // apps/shaderfit/cli.hpp
#include "mpi_communicator.hpp"

int main(int argc, char** argv) {
  int provided = 0;
  // MPI is called only from the search's own thread, never from its worker threads.
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  int status = 0;
  {
    shaderfit::mpi::MpiCommunicator world(MPI_COMM_WORLD);
    const bool leader = world.rank() == 0;
    std::ostringstream discarded, held;
    status = shaderfit::cli::run_cli(argc, argv, leader ? std::cout : discarded,
                                     leader ? std::cerr : held, &world);
    if (status != 0) {
      // Every rank stops, as the others may be waiting for it. Bad options fail on every rank
      // alike: the leader's line is the one said, so the others first give it time to abort
      // them; a rank that failed alone (a file only rank 0 can read, say) then says why.
      std::cerr.flush();
      if (!leader) {
        std::this_thread::sleep_for(std::chrono::seconds(2));
        std::cerr << "rank " << world.rank() << ": " << held.str() << std::flush;
      }
      MPI_Abort(MPI_COMM_WORLD, status);
    }
    // A rank died (batch: its entry was finished by another): MPI_Finalize would wait for it
    // for ever, so the survivors end here, their output flushed.
    if (world.lost()) {
      std::cout.flush();
      std::cerr.flush();
      std::_Exit(status);
    }
  }
  MPI_Finalize();
  return status;
}
