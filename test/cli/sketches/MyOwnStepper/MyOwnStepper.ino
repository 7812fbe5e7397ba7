// motion-sketch: stepper
// A student's own stepper sketch, as the lab might write it from scratch, for
// test/cli/test_emulate_any_sketch.py: it steps at a constant 200 steps/s (5 ms a step) to each whole
// number typed, on the RAMPS 1.4 X axis (STEP D54, DIR D55, ENABLE D38, as StepperPins.h), and prints
// only words of its own: no READY banner, no OK/DONE, no answer to `?`.
const int stepPin = 54;
const int dirPin = 55;
const int enablePin = 38;

long position = 0;
char line[16];
int lineLength = 0;

void setup()
{
    pinMode(stepPin, OUTPUT);
    pinMode(dirPin, OUTPUT);
    pinMode(enablePin, OUTPUT);
    digitalWrite(enablePin, LOW); // the driver on
    Serial.begin(9600);
    Serial.println("hello from my stepper");
}

void moveTo(long target)
{
    digitalWrite(dirPin, target > position ? HIGH : LOW);
    while (position != target) {
        digitalWrite(stepPin, HIGH);
        delayMicroseconds(10);
        digitalWrite(stepPin, LOW);
        position += target > position ? 1 : -1;
        delay(5);
    }
}

void loop()
{
    if (!Serial.available())
        return;
    char c = (char)Serial.read();
    if (c != '\r' && c != '\n') {
        if (lineLength < (int)sizeof line - 1)
            line[lineLength++] = c;
        return;
    }
    if (lineLength == 0)
        return;
    line[lineLength] = 0;
    lineLength = 0;
    long target = atol(line);
    Serial.print("going to ");
    Serial.println(target);
    moveTo(target);
    Serial.println("there");
}
