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
 *   P <port> <bit> <0|1>  drive an input pin (e.g. "P D 3 1")             -> "K"
 *   M <addr> <count>   read data memory (I/O registers, RAM)               -> "M <hex>"
 *   A <channel> <mV>   set an ADC input voltage                            -> "K"
 *   Q                  end
 *
 * If the AVR stops (crash, sleep with interrupts off) the answer is "X <state>".
 *
 * Usage: avrboard ELF MCU F_CPU_HZ UART_INDEX BAUD [EEPROM_I2C_ADDRESS EEPROM_BYTES]
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
#include <simavr/parts/i2c_eeprom.h>

#define QUEUE_BYTES (1 << 16)

static avr_t *avr;
static avr_irq_t *uart_input;
static unsigned char out[QUEUE_BYTES];
static size_t out_len;
static unsigned char in[QUEUE_BYTES];
static size_t in_head, in_tail;
static avr_cycle_count_t cycles_per_byte;
static int feeding;
static i2c_eeprom_t eeprom;
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
    avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ(uart), UART_IRQ_OUTPUT),
                            on_uart_output, NULL);

    if (argc == 8) {  /* an I2C EEPROM (24LC-class, two address bytes) on the TWI bus */
        unsigned long address = strtoul(argv[6], NULL, 0);
        size_t size = strtoul(argv[7], NULL, 0);
        i2c_eeprom_init(avr, &eeprom, (uint8_t)(address << 1), 0x01, NULL, size);
        i2c_eeprom_attach(avr, &eeprom, AVR_IOCTL_TWI_GETIRQ(0));
    }

    char line[QUEUE_BYTES * 2 + 16];
    while (fgets(line, sizeof line, stdin)) {
        char kind = line[0];
        if (kind == 'Q') break;
        if (kind == 'T') {
            avr_cycle_count_t target = strtoull(line + 2, NULL, 10);
            int state = avr->state;
            while (avr->cycle < target) {
                state = avr_run(avr);
                if (state == cpu_Done || state == cpu_Crashed) break;
            }
            if (state == cpu_Done || state == cpu_Crashed) {
                fprintf(answers, "X %d\n", state);
                fflush(answers);
                continue;
            }
            answer_hex('O', out, out_len);
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
            avr_raise_irq(avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ(port), bit), level);
            fputs("K\n", answers);
            fflush(answers);
        } else if (kind == 'A') {
            int channel = 0, millivolts = 0;
            sscanf(line + 2, "%d %d", &channel, &millivolts);
            avr_raise_irq(avr_io_getirq(avr, AVR_IOCTL_ADC_GETIRQ, channel), millivolts);
            fputs("K\n", answers);
            fflush(answers);
        } else if (kind == 'M') {
            unsigned long address = 0, count = 0;
            sscanf(line + 2, "%lu %lu", &address, &count);
            if (address + count > avr->ramend + 1UL) count = 0;
            answer_hex('M', avr->data + address, count);
        } else {
            fputs("E unknown command\n", answers);
            fflush(answers);
        }
    }
    return 0;
}
