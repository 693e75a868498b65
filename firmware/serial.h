/* serial.h - the front-panel serial line (manual 3.3). */
#ifndef SERIAL_H
#define SERIAL_H
#include "queue.h"

void serial_reset(void);
void serial_poll(void);                 /* main loop: decode received bytes */
int serial_get(mac4_msg_t *m);          /* next decoded command (source 1): 1, or 0 if none */
void serial_send(const mac4_msg_t *m);  /* a response as a telegram */

#endif
