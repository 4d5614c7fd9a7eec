/* The misuse-script mode of the C test host (misuse.c). */
#ifndef TOWCABLE_MISUSE_H
#define TOWCABLE_MISUSE_H

/* fmu_host --misuse SCRIPT FMU_DIR OTHER_FMU_DIR: argv holds the three arguments. */
int misuse_main(int argc, char **argv);

#endif
