/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The callback rule's way back: a status as a callback's return (core/callback.h). */
#include <stabdae/stabdae.h>

#include "callback.h"

int sdae__callback_code(int status) {
  if (status == SDAE_OK) return 0;
  if (status == SDAE_ERR_PHI_INV || status == SDAE_ERR_CALLBACK_RECOVERABLE) return 1;
  return -1;
}
