/* avrboard: one emulated AVR board on simavr, driven in lockstep over stdin/stdout.
 *
 * The host owns time: the board runs only when told to, so a run is deterministic and does
 * not depend on how busy the machine is.  One command per line on stdin, one answer line on
 * stdout:
 *
 *   T <cycle>          run until the AVR's cycle counter reaches <cycle> (absolute)
 *                      -> "O <hex>" every byte the board's UART sent meanwhile
 *   W <hex>            queue bytes for the board's UART receiver; they arrive one byte time
 *                      apart (10 bits at the line's baud rate), as on a real serial line
 *                      -> "K"
 *   P <port> <bit> <0|1>  drive an input pin (e.g. "P D 3 1"); from then on the pin holds
 *                      the level the host drives (and encoder pins theirs), whatever the
 *                      firmware writes to its port's pull-up bit            -> "K"
 *   M <addr> <count>   read data memory (I/O registers, RAM)               -> "M <hex>"
 *   S <cycle> <steps0> <steps1> <addr> <count>
 *                      one simulation step in one round trip: queue the encoders' steps
 *                      (set up before with E) over the span, run to <cycle>, then read
 *                      memory                                -> "O <hex> <memory hex>"
 *   A <channel> <mV>   set an ADC input voltage                            -> "K"
 *   E <n> <port> <bitA> <bitB> <steps> <cycles>
 *                      quadrature encoder n (0 or 1) on two input pins: make <steps> Gray-code
 *                      steps (negative: backwards) spread evenly over the next <cycles>, as a
 *                      turning wheel would                                  -> "K"
 *   V <flag> <addr> <count>
 *                      snapshot <count> (at most 64) bytes of data memory at <addr> each time
 *                      the byte at <flag> falls from non-zero to zero (a firmware clearing its
 *                      "update due" flag once the update is done)          -> "K"
 *   G                  the snapshots taken since the last G, oldest first
 *                      -> "G <cycle>:<hex> <cycle>:<hex> ..."
 *   R <n> <offset> <count>
 *                      read I2C EEPROM n's memory (n counts the addresses given at start-up)
 *                                                                          -> "R <hex>"
 *   Z                  reset the AVR as its reset line does (an Uno's DTR when a host opens
 *                      its port): the CPU, its RAM and peripherals start afresh, the clock
 *                      runs on; bytes on the line keep arriving (lost while the UART is off)
 *                      and encoders keep turning                           -> "K"
 *   Q                  end
 *
 * If the AVR stops (crash, sleep with interrupts off) the answer is "X <state>"; if the
 * firmware wrote above its part's RAM, "X 100".
 *
 * The data space above the part's RAM (RAMEND): an AVR core has no bus fault, so a firmware
 * reading through a wild pointer there goes on running on a board, while simavr stops the CPU
 * at such a read. The harness gives the CPU the whole 64 KiB data space, reading 0 above the
 * part's RAM (what a part returns there is undocumented; 0 ends any string at once), and
 * keeps that memory zero: a firmware that writes there (which the part would drop) stops the
 * run with "X 100" instead of reading back what it wrote. Memory commands (M, S, V) still end
 * at the part's RAMEND.
 *
 * Usage: avrboard ELF MCU F_CPU_HZ UART_INDEX BAUD [EEPROM_I2C_ADDRESSES EEPROM_BYTES]
 * (addresses comma-separated, one I2C EEPROM of EEPROM_BYTES on the TWI bus at each)
 *
 * The I2C EEPROM is the harness's own model of a Microchip 24xx-series serial EEPROM with two
 * address bytes (24LC512/24xx1025 datasheets), not simavr's example part (which holds at most
 * 4 KiB, takes the address bytes low byte first and forgets its address pointer at STOP):
 *   - control byte = its 7-bit address and R/W; it acknowledges it unless a write cycle runs;
 *   - a write: address high, address low, then data bytes into a 128-byte page buffer; the
 *     low 7 address bits wrap within the page; the page is written when the master sends
 *     STOP after at least one data byte, and for EEPROM_WRITE_CYCLE_S (tWC, the datasheet's
 *     maximum) the part then answers nothing (NACK: the master's "acknowledge polling");
 *     a repeated START instead of STOP loses the page, as on the part;
 *   - a read (after STOP or a repeated START): bytes from the address pointer, which is kept
 *     between transactions and increments after every byte read or written, rolling over at
 *     the end of the part; the master's NACK ends the read.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <simavr/sim_avr.h>
#include <simavr/sim_elf.h>
#include <simavr/sim_io.h>
#include <simavr/avr_uart.h>
#include <simavr/avr_ioport.h>
#include <simavr/avr_adc.h>
#include <simavr/avr_twi.h>
#include <simavr/sim_cycle_timers.h>
#include <simavr/sim_interrupts.h>

#define QUEUE_BYTES (1 << 16)

static avr_t *avr;
static uint16_t part_ramend; /* the part's own RAMEND; avr->ramend is the whole data space */
#define WROTE_OUTSIDE_RAM 100
static avr_irq_t *uart_input;
static unsigned char out[QUEUE_BYTES];
static size_t out_len;
static unsigned char in[QUEUE_BYTES];
static size_t in_head, in_tail;
static avr_cycle_count_t cycles_per_byte;
static int feeding;
#define EEPROM_PAGE_BYTES 128
#define EEPROM_WRITE_CYCLE_S 0.005
#define EEPROMS 4

struct eeprom {
    avr_irq_t *irq;             /* [0] to the TWI's input, [1] from its output */
    uint8_t address;            /* 7-bit I2C address */
    uint8_t *memory;
    uint32_t size;              /* bytes, a power of two */
    int selected;               /* 1: addressed for writing, 2: for reading, 0: not addressed */
    int address_bytes;          /* address bytes received in this write */
    uint32_t pointer;           /* the internal address pointer */
    uint8_t page[EEPROM_PAGE_BYTES];
    uint8_t dirty[EEPROM_PAGE_BYTES];
    uint32_t page_base;
    int data_bytes;             /* data bytes latched since the control byte */
    avr_cycle_count_t busy_until;
};
static struct eeprom eeproms[EEPROMS];
static int eeprom_count;

#define SNAPSHOT_BYTES 64
struct snapshot { avr_cycle_count_t cycle; unsigned char data[SNAPSHOT_BYTES]; };
static struct snapshot *snapshots;
static size_t snapshot_count, snapshot_capacity;
static unsigned long watch_flag, watch_address, watch_count;
static int watch_last;
struct encoder {
    char port;
    int bit_a, bit_b, wired;
    int gray;           /* 0..3: (A,B) = (0,0) (0,1) (1,1) (1,0) */
    long pending;       /* steps still to make; the sign is the direction */
    avr_cycle_count_t period;
    int running;
};
static struct encoder encoders[2];
static FILE *answers; /* the host's channel; simavr's own messages go to stderr */

static void on_uart_output(struct avr_irq_t *irq, uint32_t value, void *param) {
    (void)irq; (void)param;
    if (out_len < QUEUE_BYTES) out[out_len++] = (unsigned char)value;
}

/* One byte per byte time, however many the host queued at once. */
static avr_cycle_count_t feed_next(avr_t *board, avr_cycle_count_t when, void *param) {
    (void)board; (void)param;
    if (in_head == in_tail) { feeding = 0; return 0; }
    avr_raise_irq(uart_input, in[in_head]);
    in_head = (in_head + 1) % QUEUE_BYTES;
    return when + cycles_per_byte;
}

/* The level the host drives each input pin to, by port. simavr 1.6 re-applies an input's
 * pull-up (PORT bit set) to its pin every time the firmware writes that port (any bit:
 * digitalWrite of a motor line on PORTD), which would pull an encoder line the host holds low
 * back high for a moment: a pin the host drives is declared externally driven instead, so
 * the port keeps the host's level whatever the firmware writes. */
static uint8_t driven_mask[26], driven_value[26];

static void drive_pin(char port, int bit, int level) {
    int n = (port - 'A') % 26;
    driven_mask[n] |= (uint8_t)(1 << bit);
    if (level) driven_value[n] |= (uint8_t)(1 << bit);
    else driven_value[n] &= (uint8_t)~(1 << bit);
    avr_ioport_external_t external = {.name = port, .mask = driven_mask[n], .value = driven_value[n]};
    avr_ioctl(avr, AVR_IOCTL_IOPORT_SET_EXTERNAL(port), &external);
    avr_raise_irq(avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ(port), bit), level);
}

static void encoder_set_pins(struct encoder *e) {
    static const int a[4] = {0, 0, 1, 1}, b[4] = {0, 1, 1, 0};
    drive_pin(e->port, e->bit_a, a[e->gray]);
    drive_pin(e->port, e->bit_b, b[e->gray]);
}

static avr_cycle_count_t encoder_step(avr_t *board, avr_cycle_count_t when, void *param) {
    (void)board;
    struct encoder *e = param;
    if (e->pending == 0) { e->running = 0; return 0; }
    if (e->pending > 0) { e->gray = (e->gray + 1) & 3; e->pending--; }
    else { e->gray = (e->gray + 3) & 3; e->pending++; }
    encoder_set_pins(e);
    if (e->pending == 0) { e->running = 0; return 0; }
    return when + e->period;
}

static void encoder_queue(struct encoder *e, long steps, avr_cycle_count_t span) {
    e->pending += steps;
    long count = e->pending < 0 ? -e->pending : e->pending;
    if (count == 0) return;
    e->period = span / (avr_cycle_count_t)count;
    if (e->period < 64) e->period = 64;  /* room for the pin-change interrupt */
    if (!e->running) {
        e->running = 1;
        avr_cycle_timer_register(avr, e->period, encoder_step, e);
    }
}

static void eeprom_reply(struct eeprom *e, uint8_t msg, uint8_t data) {
    avr_raise_irq(e->irq + TWI_IRQ_INPUT, avr_twi_irq_msg(msg, e->address << 1, data));
}

/* The page buffer goes to memory: the write cycle starts. */
static void eeprom_commit(struct eeprom *e) {
    for (int i = 0; i < EEPROM_PAGE_BYTES; i++)
        if (e->dirty[i]) e->memory[(e->page_base + i) & (e->size - 1)] = e->page[i];
    memset(e->dirty, 0, sizeof e->dirty);
    e->busy_until = avr->cycle + (avr_cycle_count_t)(EEPROM_WRITE_CYCLE_S * avr->frequency);
}

static void eeprom_on_bus(struct avr_irq_t *irq, uint32_t value, void *param) {
    (void)irq;
    struct eeprom *e = param;
    avr_twi_msg_irq_t m;
    m.u.v = value;
    uint8_t msg = m.u.twi.msg;
    if (msg & TWI_COND_STOP) {
        if (e->selected == 1 && e->data_bytes > 0) eeprom_commit(e);
        e->selected = 0;
        return;
    }
    if (msg & TWI_COND_START) {  /* a control byte, after START or a repeated START */
        if (e->selected == 1) memset(e->dirty, 0, sizeof e->dirty);  /* no STOP: no write */
        e->selected = 0;
        if ((m.u.twi.addr >> 1) != e->address) return;
        if (avr->cycle < e->busy_until) return;  /* busy writing: no acknowledge */
        e->selected = (m.u.twi.addr & 1) ? 2 : 1;
        e->address_bytes = 0;
        e->data_bytes = 0;
        eeprom_reply(e, TWI_COND_ACK, 1);
        return;
    }
    if (e->selected == 1 && (msg & TWI_COND_WRITE)) {
        uint8_t data = m.u.twi.data;
        if (e->address_bytes < 2) {
            e->pointer = e->address_bytes == 0 ? (uint32_t)data << 8 : (e->pointer | data);
            e->pointer &= e->size - 1;
            e->address_bytes++;
            e->page_base = e->pointer & ~(uint32_t)(EEPROM_PAGE_BYTES - 1);
        } else {
            uint32_t in_page = e->pointer & (EEPROM_PAGE_BYTES - 1);
            e->page[in_page] = data;
            e->dirty[in_page] = 1;
            e->data_bytes++;
            e->pointer = e->page_base | ((in_page + 1) & (EEPROM_PAGE_BYTES - 1));
        }
        eeprom_reply(e, TWI_COND_ACK, 1);
        return;
    }
    if (e->selected == 2 && (msg & TWI_COND_READ)) {
        eeprom_reply(e, TWI_COND_READ, e->memory[e->pointer]);
        e->pointer = (e->pointer + 1) & (e->size - 1);
        if (!(msg & TWI_COND_ACK)) e->selected = 0;  /* the master's NACK: the read is over */
    }
}

static void eeprom_attach(uint8_t address, uint32_t size) {
    static const char *names[2] = {"8>eeprom.out", "32<eeprom.in"};
    struct eeprom *e = &eeproms[eeprom_count++];
    memset(e, 0, sizeof *e);
    e->address = address;
    e->size = size;
    e->memory = malloc(size);
    memset(e->memory, 0xff, size);  /* erased, as delivered */
    e->irq = avr_alloc_irq(&avr->irq_pool, 0, 2, names);
    avr_irq_register_notify(e->irq + TWI_IRQ_OUTPUT, eeprom_on_bus, e);
    avr_connect_irq(e->irq + TWI_IRQ_INPUT, avr_io_getirq(avr, AVR_IOCTL_TWI_GETIRQ(0), TWI_IRQ_INPUT));
    avr_connect_irq(avr_io_getirq(avr, AVR_IOCTL_TWI_GETIRQ(0), TWI_IRQ_OUTPUT), e->irq + TWI_IRQ_OUTPUT);
}

static void watch(void) {
    int level = avr->data[watch_flag] != 0;
    if (watch_last && !level) {
        if (snapshot_count == snapshot_capacity) {
            snapshot_capacity = snapshot_capacity ? 2 * snapshot_capacity : 256;
            snapshots = realloc(snapshots, snapshot_capacity * sizeof *snapshots);
        }
        snapshots[snapshot_count].cycle = avr->cycle;
        memcpy(snapshots[snapshot_count].data, avr->data + watch_address, watch_count);
        snapshot_count++;
    }
    watch_last = level;
}

/* simavr 1.6 counts every UART frame as start + data + parity + stop bits, a parity bit
 * even when the frame has none (avr_uart_baud_write counts "1 parity" in every word), so an 8N1 byte takes
 * 11 bit times there where the USART sends 10: at 57600 baud on a 16 MHz part (UBRR 16, no
 * U2X: 272 cycles a bit) 2992 cycles, 187 us, instead of 2720, 170 us. It paces both the
 * bytes the firmware sends and the bytes it receives by that time. Once simavr has set the
 * frame time (at the write of UBRRnL), the harness sets it again to the USART's: its bit
 * time (from UBRR and U2X, as simavr reckons it) times the bits of the frame, with a parity
 * bit only when UCSRnC's UPMn1 bit enables parity. */
static avr_uart_t *host_uart;

static void uart_frame_fix(struct avr_t *board, avr_io_addr_t addr, uint8_t v, void *param) {
    (void)addr; (void)v; (void)param;
    avr_uart_t *p = host_uart;
    static const int databits[] = {5, 6, 7, 8, 8, 8, 8, 9};
    int db = databits[avr_regbit_get(board, p->ucsz) | (avr_regbit_get(board, p->ucsz2) << 2)];
    int sb = 1 + avr_regbit_get(board, p->usbs);
    int parity = p->r_ucsrc ? (board->data[p->r_ucsrc] >> 5) & 1 : 0;
    avr_cycle_count_t bit = p->cycles_per_byte / (avr_cycle_count_t)(1 + db + 1 + sb);
    p->cycles_per_byte = bit * (avr_cycle_count_t)(1 + db + parity + sb);
}

/* simavr 1.6 raises UDRE (the data register empty) only once the byte on the line has been
 * sent, so the firmware has one place for a byte, the shift register. The USART has two: a
 * byte written to UDRn while the line is idle moves on into the shift register at once, and
 * UDRn takes the next byte while it is sent; UDRE rises again when that byte moves on, at the
 * end of the one before. The harness raises UDRE at those two moments (simavr's transmit
 * pump, which ends each byte, is found once among the cycle timers: the one the first byte
 * written started, with nothing on the receive side). */
static avr_cycle_timer_t tx_pump;

static avr_cycle_timer_t find_tx_pump(avr_uart_t *p) {
    avr_cycle_timer_t found = NULL;
    int count = 0;
    for (avr_cycle_timer_slot_p slot = avr->cycle_timers.timer; slot; slot = slot->next)
        if (slot->param == p) { found = slot->timer; count++; }
    return count == 1 && p->input.read == p->input.write ? found : NULL;  /* receive fifo empty */
}

static avr_cycle_count_t udr_moved_on(struct avr_t *board, avr_cycle_count_t when, void *param) {
    (void)when; (void)param;
    if (host_uart->tx_cnt == 1) avr_raise_interrupt(board, &host_uart->udrc);
    return 0;
}

static void udr_written(struct avr_t *board, avr_io_addr_t addr, uint8_t v, void *param) {
    (void)addr; (void)v; (void)param;
    avr_uart_t *p = host_uart;
    if (!avr_regbit_get(board, p->txen) || !p->udrc.vector) return;
    if (!tx_pump) tx_pump = find_tx_pump(p);
    if (!tx_pump) return;
    if (p->tx_cnt == 1) {
        avr_raise_interrupt(board, &p->udrc);  /* into the shift register: UDRn is free */
    } else if (p->tx_cnt == 2) {
        /* waits in UDRn until the byte on the line ends (the pump's next call), then moves on;
         * a cycle after the pump, which clears UDRE while a byte is still on the line */
        avr_cycle_count_t left = avr_cycle_timer_status(board, tx_pump, p);
        if (left) avr_cycle_timer_register(board, left + 1, udr_moved_on, NULL);
    }
}

static void uart_frame_fix_attach(char name) {
    for (avr_io_t *io = avr->io_port; io; io = io->next) {
        if (strcmp(io->kind, "uart") != 0 || ((avr_uart_t *)io)->name != name) continue;
        host_uart = (avr_uart_t *)io;
        /* registered after simavr's own handlers: simavr's io muxer calls them in order */
        avr_register_io_write(avr, host_uart->ubrrl.reg, uart_frame_fix, NULL);
        avr_register_io_write(avr, host_uart->r_udr, udr_written, NULL);
        return;
    }
}

static int outside_ram_written(void) {
    for (unsigned long address = part_ramend + 1UL; address <= avr->ramend; address++)
        if (avr->data[address]) return 1;
    return 0;
}

static int run_to(avr_cycle_count_t target) {
    int state = avr->state;
    while (avr->cycle < target) {
        state = avr_run(avr);
        if (state == cpu_Done || state == cpu_Crashed) return state;
        if (watch_count) watch();
    }
    return outside_ram_written() ? WROTE_OUTSIDE_RAM : -1;
}

static int hexval(int c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

static void answer_hex(char kind, const unsigned char *data, size_t len) {
    static const char digits[] = "0123456789abcdef";
    fputc(kind, answers);
    fputc(' ', answers);
    for (size_t i = 0; i < len; i++) {
        fputc(digits[data[i] >> 4], answers);
        fputc(digits[data[i] & 15], answers);
    }
    fputc('\n', answers);
    fflush(answers);
}

int main(int argc, char **argv) {
    if (argc != 6 && argc != 8) {
        fprintf(stderr, "usage: %s ELF MCU F_CPU UART BAUD [EEPROM_ADDR EEPROM_BYTES]\n", argv[0]);
        return 2;
    }
    answers = fdopen(dup(1), "w");
    dup2(2, 1);
    elf_firmware_t firmware;
    memset(&firmware, 0, sizeof firmware);
    if (elf_read_firmware(argv[1], &firmware) != 0) {
        fprintf(stderr, "cannot read %s\n", argv[1]);
        return 2;
    }
    strncpy(firmware.mmcu, argv[2], sizeof firmware.mmcu - 1);
    firmware.frequency = strtoul(argv[3], NULL, 10);
    avr = avr_make_mcu_by_name(firmware.mmcu);
    if (!avr) {
        fprintf(stderr, "simavr has no %s\n", firmware.mmcu);
        return 2;
    }
    part_ramend = avr->ramend;
    avr->ramend = 0xffff; /* read before avr_init, which sizes the data memory from it */
    avr_init(avr);
    avr->log = 0;
    avr_load_firmware(avr, &firmware);

    char uart = argv[4][0];
    unsigned long baud = strtoul(argv[5], NULL, 10);
    cycles_per_byte = (avr_cycle_count_t)(firmware.frequency * 10ULL / baud);
    uint32_t flags = 0;
    avr_ioctl(avr, AVR_IOCTL_UART_GET_FLAGS(uart), &flags);
    flags &= ~AVR_UART_FLAG_STDIO;  /* bytes go to the host, never to simavr's console */
    avr_ioctl(avr, AVR_IOCTL_UART_SET_FLAGS(uart), &flags);
    uart_input = avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ(uart), UART_IRQ_INPUT);
    uart_frame_fix_attach(uart);
    avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ(uart), UART_IRQ_OUTPUT),
                            on_uart_output, NULL);

    if (argc == 8) {  /* I2C EEPROMs (24xx-series, two address bytes) on the TWI bus */
        uint32_t size = strtoul(argv[7], NULL, 0);
        char *next = argv[6];
        while (eeprom_count < EEPROMS && *next) {
            eeprom_attach((uint8_t)strtoul(next, &next, 0), size);
            if (*next == ',') next++;
        }
    }

    char line[QUEUE_BYTES * 2 + 16];
    while (fgets(line, sizeof line, stdin)) {
        char kind = line[0];
        if (kind == 'Q') break;
        if (kind == 'T' || kind == 'S') {
            unsigned long long target = 0;
            long steps0 = 0, steps1 = 0;
            unsigned long address = 0, count = 0;
            if (kind == 'T') {
                target = strtoull(line + 2, NULL, 10);
            } else {
                sscanf(line + 2, "%llu %ld %ld %lu %lu", &target, &steps0, &steps1, &address, &count);
                avr_cycle_count_t span = target > avr->cycle ? target - avr->cycle : 1;
                if (encoders[0].wired) encoder_queue(&encoders[0], steps0, span);
                if (encoders[1].wired) encoder_queue(&encoders[1], steps1, span);
            }
            int state = run_to(target);
            if (state >= 0) {
                fprintf(answers, "X %d\n", state);
                fflush(answers);
                continue;
            }
            if (kind == 'T') {
                answer_hex('O', out, out_len);
            } else {
                static const char digits[] = "0123456789abcdef";
                if (address + count > part_ramend + 1UL) count = 0;
                fputs("O ", answers);
                for (size_t i = 0; i < out_len; i++) {
                    fputc(digits[out[i] >> 4], answers);
                    fputc(digits[out[i] & 15], answers);
                }
                fputc(' ', answers);
                for (unsigned long i = 0; i < count; i++) {
                    fputc(digits[avr->data[address + i] >> 4], answers);
                    fputc(digits[avr->data[address + i] & 15], answers);
                }
                fputc('\n', answers);
                fflush(answers);
            }
            out_len = 0;
        } else if (kind == 'W') {
            for (char *p = line + 2; hexval(p[0]) >= 0 && hexval(p[1]) >= 0; p += 2) {
                size_t next = (in_tail + 1) % QUEUE_BYTES;
                if (next == in_head) break;
                in[in_tail] = (unsigned char)(hexval(p[0]) * 16 + hexval(p[1]));
                in_tail = next;
            }
            if (!feeding && in_head != in_tail) {
                feeding = 1;
                avr_cycle_timer_register(avr, 1, feed_next, NULL);
            }
            fputs("K\n", answers);
            fflush(answers);
        } else if (kind == 'P') {
            char port = 0;
            int bit = 0, level = 0;
            sscanf(line + 2, "%c %d %d", &port, &bit, &level);
            drive_pin(port, bit, level);
            fputs("K\n", answers);
            fflush(answers);
        } else if (kind == 'A') {
            int channel = 0, millivolts = 0;
            sscanf(line + 2, "%d %d", &channel, &millivolts);
            avr_raise_irq(avr_io_getirq(avr, AVR_IOCTL_ADC_GETIRQ, channel), millivolts);
            fputs("K\n", answers);
            fflush(answers);
        } else if (kind == 'E') {
            int n = 0, bit_a = 0, bit_b = 0;
            char port = 0;
            long steps = 0;
            unsigned long long span = 0;
            sscanf(line + 2, "%d %c %d %d %ld %llu", &n, &port, &bit_a, &bit_b, &steps, &span);
            struct encoder *e = &encoders[n & 1];
            if (!e->wired || e->port != port || e->bit_a != bit_a || e->bit_b != bit_b) {
                e->wired = 1;  /* first use: both pins low */
                e->port = port;
                e->bit_a = bit_a;
                e->bit_b = bit_b;
                e->gray = 0;
                encoder_set_pins(e);
            }
            encoder_queue(e, steps, span);
            fputs("K\n", answers);
            fflush(answers);
        } else if (kind == 'V') {
            sscanf(line + 2, "%lu %lu %lu", &watch_flag, &watch_address, &watch_count);
            if (watch_count > SNAPSHOT_BYTES || watch_flag > part_ramend
                || watch_address + watch_count > part_ramend + 1UL) watch_count = 0;
            watch_last = watch_count ? avr->data[watch_flag] != 0 : 0;
            fputs("K\n", answers);
            fflush(answers);
        } else if (kind == 'G') {
            static const char digits[] = "0123456789abcdef";
            fputc('G', answers);
            for (size_t i = 0; i < snapshot_count; i++) {
                fprintf(answers, " %llu:", (unsigned long long)snapshots[i].cycle);
                for (unsigned long j = 0; j < watch_count; j++) {
                    fputc(digits[snapshots[i].data[j] >> 4], answers);
                    fputc(digits[snapshots[i].data[j] & 15], answers);
                }
            }
            fputc('\n', answers);
            fflush(answers);
            snapshot_count = 0;
        } else if (kind == 'R') {
            int n = 0;
            unsigned long offset = 0, count = 0;
            sscanf(line + 2, "%d %lu %lu", &n, &offset, &count);
            if (n < 0 || n >= eeprom_count || offset + count > eeproms[n].size) count = 0;
            answer_hex('R', count ? eeproms[n].memory + offset : NULL, count);
        } else if (kind == 'Z') {
            /* avr_reset also drops every cycle timer: the line's and the encoders' own go on */
            avr_reset(avr);
            avr->state = cpu_Running;
            if (in_head != in_tail) avr_cycle_timer_register(avr, cycles_per_byte, feed_next, NULL);
            else feeding = 0;
            for (int n = 0; n < 2; n++) {
                encoders[n].running = 0;
                if (encoders[n].wired && encoders[n].pending) {
                    encoders[n].running = 1;
                    avr_cycle_timer_register(avr, encoders[n].period, encoder_step, &encoders[n]);
                }
            }
            fputs("K\n", answers);
            fflush(answers);
        } else if (kind == 'M') {
            unsigned long address = 0, count = 0;
            sscanf(line + 2, "%lu %lu", &address, &count);
            if (address + count > part_ramend + 1UL) count = 0;
            answer_hex('M', avr->data + address, count);
        } else {
            fputs("E unknown command\n", answers);
            fflush(answers);
        }
    }
    return 0;
}
